/* The firmware's main loop: wait for a tick's sensor frames, step the
 * mind, send its actuator frames; when sensor frames stop for longer than
 * the link timeout, set every actuator to neutral until they come back.
 * Meanwhile a new mind may arrive over the bus (evo flash): it is written
 * into the mind slot the running mind does not use, and the firmware
 * switches to it between two ticks once it is checked.
 *
 * The mind image is used in place where it lies in flash (a mind slot,
 * mind_slot.c); only its state is in RAM. The wire is docs/wire.md, the
 * exit statuses and log lines docs/firmware.md. */
#include <stddef.h>
#include <stdint.h>

#include "board.h"
#include "evo/flash.h"
#include "evo/mind.h"
#include "evo/wire.h"
#include "mind_slot.h"

/* The robot's key (make firmware FW_KEY=FILE): FW_FLASH_KEY, its bytes,
 * when it has one; then transfers and CONFIG frames need it. */
#include "flash_key.h"

#ifndef FW_BOT
#error "build with -DFW_BOT=\"bots/NAME.h\" (the robot's names)"
#endif
#include FW_BOT

/* Bytes of RAM for the mind state (evo_state_size); a mind that needs
 * more is refused. */
#ifndef FW_STATE_BYTES
#define FW_STATE_BYTES 1024
#endif

/* Milliseconds without a sensor frame before the actuators go neutral;
 * an EVO_WIRE_CONFIG frame changes it at run time, up to
 * FW_LINK_TIMEOUT_MAX_MS: a node on the bus cannot leave the motors
 * running on stale commands for longer than that. */
#ifndef FW_LINK_TIMEOUT_MS
#define FW_LINK_TIMEOUT_MS 100
#endif
#ifndef FW_LINK_TIMEOUT_MAX_MS
#define FW_LINK_TIMEOUT_MAX_MS 10000
#endif
_Static_assert(FW_LINK_TIMEOUT_MS >= 1 &&
		   FW_LINK_TIMEOUT_MS <= FW_LINK_TIMEOUT_MAX_MS &&
		   FW_LINK_TIMEOUT_MAX_MS <= 65535,
	       "link timeout: 1 <= FW_LINK_TIMEOUT_MS <= "
	       "FW_LINK_TIMEOUT_MAX_MS <= 65535");

/* 1: minds arrive over the bus (evo flash); 0: the firmware runs the mind
 * it was built with only (make firmware-size builds both, to show what
 * receiving a mind costs). */
#ifndef FW_FLASH
#define FW_FLASH 1
#endif

/* Milliseconds without a frame of a transfer before it is abandoned. */
#ifndef FW_FLASH_TIMEOUT_MS
#define FW_FLASH_TIMEOUT_MS 3000
#endif

/* Most segments of a transfer in flight that the robot grants. */
#ifndef FW_FLASH_WINDOW
#define FW_FLASH_WINDOW 32
#endif

/* Exit statuses (docs/firmware.md). */
enum {
	FW_EXIT_IMAGE_CORRUPT = 3,  /* not an image, truncated, CRC */
	FW_EXIT_IMAGE_MISMATCH = 4, /* built for other names */
	FW_EXIT_IMAGE_INVALID = 5,  /* bad layout, unknown class */
	FW_EXIT_NO_RAM = 6,	    /* state larger than FW_STATE_BYTES */
	FW_EXIT_OTHER = 8,
};

static const char *const sensor_names[] = {FW_BOT_SENSORS 0};
static const char *const actuator_names[] = {FW_BOT_ACTUATORS 0};
static const char *const var_names[] = {FW_BOT_VARIABLES 0};
#define N_SENSORS	(sizeof sensor_names / sizeof *sensor_names - 1)
#define N_ACTUATORS	(sizeof actuator_names / sizeof *actuator_names - 1)
#define N_VARS		(sizeof var_names / sizeof *var_names - 1)
#define N_SENSOR_FRAMES ((N_SENSORS + 1) / 2)
/* Every sensor frame of a tick, bit k for frame k. */
#define ALL_SENSOR_FRAMES                                                      \
	(N_SENSOR_FRAMES == 64 ? ~(uint64_t)0                                  \
			       : ((uint64_t)1 << (N_SENSOR_FRAMES % 64)) - 1)

_Static_assert(N_SENSORS <= 2 * EVO_WIRE_SENSOR_FRAMES, "too many sensors");
_Static_assert(N_ACTUATORS <= 2 * EVO_WIRE_ACTUATOR_FRAMES,
	       "too many actuators");
_Static_assert(N_SENSORS > 0 && N_ACTUATORS > 0, "a robot senses and acts");

static _Alignas(8) uint8_t state_mem[FW_STATE_BYTES];
static evo_q16 sensors[N_SENSORS], actuators[N_ACTUATORS];

/* The running mind, its state, and the slot it lies in. */
static evo_mind mind;
static evo_state *state;
static unsigned running_slot;

/* ---- output --------------------------------------------------------- */

static void put_str(const char *s)
{
	while (*s)
		board_putc((uint8_t)*s++);
}

static void put_uint(uint32_t v)
{
	char buf[11];
	int i = sizeof buf;
	buf[--i] = 0;
	do {
		buf[--i] = (char)('0' + v % 10u);
		v /= 10u;
	} while (v);
	put_str(buf + i);
}

static void put_hex32(uint32_t v)
{
	for (int shift = 28; shift >= 0; shift -= 4)
		board_putc((uint8_t) "0123456789abcdef"[(v >> shift) & 0xFu]);
}

static void send_frame(const evo_can_frame *f)
{
	char line[EVO_SLCAN_LINE_MAX + 1];
	size_t n = evo_slcan_encode(f, line);
	for (size_t i = 0; i < n; i++)
		board_putc((uint8_t)line[i]);
}

static void send_actuators(uint32_t tick, uint8_t flags)
{
	evo_can_frame f;
	for (unsigned k = 0; k < evo_wire_frames(N_ACTUATORS); k++) {
		evo_wire_pack(EVO_WIRE_ACTUATOR, actuators, N_ACTUATORS, k, &f);
		send_frame(&f);
	}
	f.id = EVO_WIRE_TICKED;
	f.len = 5;
	evo_wire_put_u32(f.data, tick);
	f.data[4] = flags;
	send_frame(&f);
}

/* ---- refusing an image ---------------------------------------------- */

static int exit_status(evo_status st)
{
	switch (st) {
	case EVO_ERR_ALIGN:
	case EVO_ERR_IMAGE_MAGIC:
	case EVO_ERR_IMAGE_VERSION:
	case EVO_ERR_IMAGE_LENGTH:
	case EVO_ERR_IMAGE_CRC:
		return FW_EXIT_IMAGE_CORRUPT;
	case EVO_ERR_IMAGE_NAMES:
		return FW_EXIT_IMAGE_MISMATCH;
	case EVO_ERR_IMAGE_LAYOUT:
	case EVO_ERR_IMAGE_CLASS:
	case EVO_ERR_IMAGE_RANGE:
		return FW_EXIT_IMAGE_INVALID;
	default:
		return FW_EXIT_OTHER;
	}
}

__attribute__((noreturn)) static void refuse(evo_status st, uint32_t names_hash)
{
	put_str("# evo firmware: mind image refused: ");
	put_str(evo_status_str(st));
	if (st == EVO_ERR_IMAGE_NAMES) {
		/* The header's names hash is at byte 16 (docs/mind-image.md).
		 */
		put_str(" (image built for names ");
		put_hex32(evo_wire_get_u32(fw_slot[0] + 16));
		put_str(", this robot's ");
		put_str(FW_BOT_NAME);
		put_str(" has ");
		put_hex32(names_hash);
		put_str(")");
	}
	put_str("\r\n");
	board_exit(exit_status(st));
}

/* ---- the loop ------------------------------------------------------- */

typedef struct link_state {
	uint32_t last_ms; /* when the last sensor or tick frame came */
	uint32_t timeout_ms;
	int up;		    /* sensor frames are coming */
	uint64_t got;	    /* sensor frames received this tick, bit k */
	uint64_t known;	    /* sensor frames received since the link came up */
	uint32_t last_tick; /* the last tick number received */
	uint32_t ticks, incomplete, link_losses;
	uint32_t bad[EVO_WIRE_BAD_COUNT];
} link_state;

static void count_bad(link_state *l, evo_wire_bad why)
{
	l->bad[why]++;
}

static uint16_t sat16(uint32_t v)
{
	return v > 0xFFFFu ? 0xFFFFu : (uint16_t)v;
}

static void send_status(const link_state *l)
{
	evo_can_frame f;
	f.id = EVO_WIRE_STATUS_LINES;
	f.len = 8;
	for (unsigned i = 0; i < EVO_WIRE_BAD_COUNT; i++)
		evo_wire_put_u16(f.data + 2 * i, sat16(l->bad[i]));
	send_frame(&f);
	f.id = EVO_WIRE_STATUS_LINK;
	evo_wire_put_u32(f.data, l->ticks);
	evo_wire_put_u16(f.data + 4, sat16(l->incomplete));
	evo_wire_put_u16(f.data + 6, sat16(l->link_losses));
	send_frame(&f);
}

static void go_neutral(link_state *l)
{
	for (unsigned a = 0; a < N_ACTUATORS; a++)
		actuators[a] = EVO_Q16_HALF;
	board_actuate(actuators, N_ACTUATORS);
	send_actuators(l->last_tick, EVO_WIRE_F_NEUTRAL);
}

/* "# mind NAME: image N bytes in flash at ADDR, state N bytes in RAM" */
static void put_mind(void)
{
	put_str("# mind ");
	put_str(evo_mind_skill_name(&mind, 0));
	put_str(": image ");
	put_uint(mind.length);
	put_str(" bytes in flash at ");
	put_hex32((uint32_t)(uintptr_t)fw_slot[running_slot]);
	put_str(", state ");
	put_uint((uint32_t)evo_state_size(&mind));
	put_str(" bytes in RAM");
}

#if FW_FLASH
static evo_flash_rx flash_rx;
#ifdef FW_FLASH_KEY
static const uint8_t flash_key[] = {FW_FLASH_KEY};
_Static_assert(sizeof flash_key >= EVO_FLASH_KEY_MIN &&
		   sizeof flash_key <= EVO_FLASH_KEY_MAX,
	       "a key is 16 to 64 bytes");
#endif

static void send_replies(const evo_can_frame *reply)
{
	for (unsigned i = 0; i < flash_rx.replies; i++)
		send_frame(&reply[i]);
}

/* The receiver checked the new mind (CRC, image, state size): run it from
 * the next tick on, with a fresh state, and tell the host. The old slot
 * no longer boots and takes the next transfer. Between two ticks, so no
 * tick is computed by half of each. */
static void switch_mind(const link_state *l)
{
	unsigned old = running_slot;
	mind = flash_rx.mind;
	/* Cannot fail: the receiver checked the size against state_mem. */
	evo_state_init(&mind, state_mem, sizeof state_mem, &state);
	running_slot = 1u - old;
	fw_slot_retire(old);
	evo_flash_rx_target(&flash_rx, fw_slot[old], (uint32_t)fw_slot_size());
	evo_can_frame reply[EVO_FLASH_RX_REPLIES];
	evo_flash_rx_switched(&flash_rx, l->last_tick, reply);
	send_replies(reply);
	put_mind();
	put_str("; from the tick after ");
	put_uint(l->last_tick);
	put_str("; transfer counter ");
	put_uint(flash_rx.counter);
	put_str("\r\n");
}

static void on_flash(const link_state *l, const evo_can_frame *f)
{
	evo_can_frame reply[EVO_FLASH_RX_REPLIES];
	switch (evo_flash_rx_frame(&flash_rx, f, board_millis(), reply)) {
	case EVO_FLASH_RX_REPLY:
		send_replies(reply);
		return;
	case EVO_FLASH_RX_SWITCH:
		switch_mind(l);
		return;
	default:
		return;
	}
}
#endif

static void on_frame(link_state *l, const evo_can_frame *f)
{
	if (f->id >= EVO_WIRE_SENSOR &&
	    f->id < EVO_WIRE_SENSOR + EVO_WIRE_SENSOR_FRAMES) {
		int k = evo_wire_unpack(EVO_WIRE_SENSOR, f, sensors, N_SENSORS);
		if (k < 0) {
			count_bad(l, (evo_wire_bad)(-1 - k));
			return;
		}
		l->got |= (uint64_t)1 << k;
		l->last_ms = board_millis();
		l->up = 1;
		return;
	}
	switch (f->id) {
	case EVO_WIRE_TICK: {
		/* DLC 4: all frames were sent; DLC 8: those of the mask, the
		 * others keep their values (docs/wire.md). */
		if (f->len != 4 && (f->len != 8 || N_SENSOR_FRAMES > 32)) {
			count_bad(l, EVO_WIRE_BAD_LENGTH);
			return;
		}
		uint64_t sent = f->len == 4 ? ALL_SENSOR_FRAMES
					    : evo_wire_get_u32(f->data + 4);
		l->last_tick = evo_wire_get_u32(f->data);
		l->last_ms = board_millis();
		l->up = 1;
		l->known |= l->got;
		int complete = l->got == sent && l->known == ALL_SENSOR_FRAMES;
		l->got = 0;
		if (!complete) {
			l->incomplete++;
			send_actuators(l->last_tick, EVO_WIRE_F_INCOMPLETE);
			return;
		}
		evo_mind_step(&mind, state, sensors, actuators);
		board_actuate(actuators, N_ACTUATORS);
		l->ticks++;
		send_actuators(l->last_tick, 0);
		return;
	}
	case EVO_WIRE_STATUS_REQ:
		if (f->len != 0) {
			count_bad(l, EVO_WIRE_BAD_LENGTH);
			return;
		}
		send_status(l);
		return;
	case EVO_WIRE_CONFIG: {
		/* With a key, only a CONFIG with its tag (evo/flash.h) */
		uint32_t ms = 0;
#if FW_FLASH
		int ok = evo_flash_config_check(&flash_rx, f, &ms);
#else
		int ok = f->len == 2;
		if (ok)
			ms = evo_wire_get_u16(f->data);
#endif
		if (!ok) {
			count_bad(l, EVO_WIRE_BAD_LENGTH);
			return;
		}
		l->timeout_ms = ms == 0			       ? 1u
				: ms > FW_LINK_TIMEOUT_MAX_MS ? FW_LINK_TIMEOUT_MAX_MS
							       : ms;
		return;
	}
#if FW_FLASH
	case EVO_FLASH_BEGIN:
	case EVO_FLASH_DATA:
	case EVO_FLASH_AUTH:
	case EVO_FLASH_END:
		on_flash(l, f);
		return;
#endif
	default:
		count_bad(l, EVO_WIRE_BAD_ID);
		return;
	}
}

int main(void)
{
	board_init();
	put_str("# evo firmware on ");
	put_str(board_name);
	put_str(", robot ");
	put_str(FW_BOT_NAME);
	put_str("\r\n");

	uint32_t names_hash =
	    evo_names_hash(sensor_names, N_SENSORS, actuator_names, N_ACTUATORS,
			   var_names, N_VARS);
	/* The built-in slot's mind, unless evo flash has put a mind in the
	 * other slot since, which then retired it (a slot that does not
	 * open is skipped; both do only if the power failed between a switch
	 * and the retiring). A refusal names the built-in slot's reason. */
	evo_status st =
	    evo_mind_open(fw_slot[0], fw_slot_size(), names_hash, &mind);
#if FW_FLASH
	if (st != EVO_OK && evo_mind_open(fw_slot[1], fw_slot_size(),
					  names_hash, &mind) == EVO_OK) {
		st = EVO_OK;
		running_slot = 1;
	}
#endif
	if (st != EVO_OK)
		refuse(st, names_hash);
	size_t need = evo_state_size(&mind);
	if (need > sizeof state_mem) {
		put_str("# evo firmware: the mind state needs ");
		put_uint((uint32_t)need);
		put_str(" bytes of RAM; this firmware has ");
		put_uint(sizeof state_mem);
		put_str(" (FW_STATE_BYTES)\r\n");
		board_exit(FW_EXIT_NO_RAM);
	}
	st = evo_state_init(&mind, state_mem, sizeof state_mem, &state);
	if (st != EVO_OK)
		refuse(st, names_hash);
#if FW_FLASH
	evo_flash_rx_def def = {names_hash,	     sizeof state_mem,
				FW_FLASH_TIMEOUT_MS, FW_FLASH_WINDOW,
				fw_slot_write,	     &flash_rx,
				NULL,		     0};
#ifdef FW_FLASH_KEY
	def.key = flash_key;
	def.key_len = sizeof flash_key;
#endif
	evo_flash_rx_init(&flash_rx, &def);
	evo_flash_rx_target(&flash_rx, fw_slot[1u - running_slot],
			    (uint32_t)fw_slot_size());
	/* The running mind's transfer counter, kept in its slot after the
	 * image: a robot started again refuses what it refused before. */
	flash_rx.counter =
	    evo_flash_rx_counter_at(fw_slot[running_slot],
				    (uint32_t)fw_slot_size(), mind.length);
#endif

	link_state l = {0};
	l.timeout_ms = FW_LINK_TIMEOUT_MS;
	for (unsigned a = 0; a < N_ACTUATORS; a++)
		actuators[a] = EVO_Q16_HALF;
	board_actuate(actuators, N_ACTUATORS);

	put_mind();
	put_str("; names ");
	put_hex32(names_hash);
	put_str("; link timeout ");
	put_uint(l.timeout_ms);
	put_str(" ms");
#if FW_FLASH
	put_str("; transfer counter ");
	put_uint(flash_rx.counter);
#ifdef FW_FLASH_KEY
	put_str("; transfers need the key");
#endif
#endif
	put_str("\r\n");
	evo_can_frame f;
	f.id = EVO_WIRE_HELLO;
	f.len = 8;
	evo_wire_put_u32(f.data, names_hash);
	f.data[4] = (uint8_t)N_SENSORS;
	f.data[5] = (uint8_t)N_ACTUATORS;
	f.data[6] = (uint8_t)N_VARS;
	f.data[7] = EVO_WIRE_VERSION;
	send_frame(&f);

	evo_slcan_rx rx;
	evo_slcan_rx_init(&rx);
	for (;;) {
		int c = board_getc();
		if (c < 0) {
			board_idle();
		} else {
			evo_wire_bad why;
			switch (evo_slcan_rx_byte(&rx, (uint8_t)c, &f, &why)) {
			case EVO_SLCAN_FRAME:
				on_frame(&l, &f);
				break;
			case EVO_SLCAN_BAD:
				count_bad(&l, why);
				break;
			default:
				break;
			}
		}
#if FW_FLASH
		/* Only while a transfer is under way: the loop runs per byte,
		 * and a call per byte would cost the ticks. */
		if (flash_rx.active &&
		    evo_flash_rx_poll(&flash_rx, board_millis(), &f) ==
			EVO_FLASH_RX_REPLY)
			send_frame(&f); /* a refusal: one frame, no tag */
#endif
		/* Unsigned difference: right across the clock's wrap. */
		if (l.up && board_millis() - l.last_ms > l.timeout_ms) {
			l.up = 0;
			l.got = 0;
			l.known = 0; /* the next tick must bring every frame */
			l.link_losses++;
			go_neutral(&l);
		}
	}
}
