/* The firmware under QEMU (make firmware-test): for each firmware given,
 *   - a trace recorded by `evo run --trace` is replayed as sensor frames and
 *     every actuator value the firmware sends back must equal the trace's;
 *   - when sensor frames stop, the actuators go neutral within the link
 *     timeout, and the mind goes on as before when frames come back;
 *   - malformed lines are counted by reason and ignored;
 *   - a tick with a sensor frame missing is not stepped;
 *   - a corrupt image, one built for another botdesc, one with a network
 *     weight out of range, and an empty mind slot are refused, with the
 *     reason and a distinct exit status;
 *   - `evo flash` puts a newly trained mind onto the running firmware
 *     between two ticks: every actuator value equals the old mind's trace
 *     before the switch and the new mind's after it; a lost frame is sent
 *     again; a transfer cut at a random frame, a corrupted segment and
 *     another robot's image leave the old mind ticking, and evo flash
 *     says why.
 * Ends with "N passed, N failed"; exits non-zero on a failure.
 *
 * usage: firmware_test --qemu QEMU --objcopy OBJCOPY --trace TRACE
 *        --image MIND.bin --other-image OTHER.bin --tmp DIR
 *        --evo EVO --new-mind DIR --new-trace TRACE --other-mind DIR
 *        --seed N --firmware MACHINE=ELF [--firmware MACHINE=ELF ...] */
#define _POSIX_C_SOURCE 200809L
#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "evo/flash.h"
#include "evo/image.h"
#include "evo/net.h"
#include "harness.h"
#include "host/qemu_session.h"
#include "host/trace_file.h"
#include "remote/can.h"

#define SLOT_BYTES	    8192 /* the MIND region of firmware/m0.ld and m3.ld */
#define EXIT_IMAGE_CORRUPT  3
#define EXIT_IMAGE_MISMATCH 4
#define EXIT_IMAGE_INVALID  5

static struct {
	const char *qemu, *objcopy, *trace_path, *image, *other_image, *tmp;
	const char *evo, *new_mind, *new_trace, *other_mind;
	unsigned long seed;
	const char *machine[4], *elf[4];
	unsigned n_fw;
	const char *key_path; /* --key: the keyed firmware's key file */
	const char *keyed_machine[4], *keyed_elf[4];
	unsigned n_keyed;
} opt;

/* The test key's bytes (--key), for the keyed firmware's CONFIG. */
static uint8_t test_key[EVO_FLASH_KEY_MAX];
static size_t test_key_len;
/* The firmware under test has the key (its CONFIG needs the tag). */
static int elf_keyed;

static trace_file trace, new_trace;
static const char *machine, *elf; /* the firmware under test */

/* ---- helpers ---------------------------------------------------------- */

static int start(qemu_session *q, const char *kernel, double deadline_s)
{
	char err[256], errfile[512];
	snprintf(errfile, sizeof errfile, "%s/qemu-%s.stderr", opt.tmp,
		 machine);
	qemu_opts o = {opt.qemu, machine, kernel, NULL, errfile, deadline_s};
	if (qs_start(q, &o, err, sizeof err) != 0) {
		printf("  cannot start %s: %s\n", opt.qemu, err);
		return -1;
	}
	return 0;
}

/* A link timeout long enough that a busy host cannot trip it: for the
 * tests that are not about link loss. */
static void patient_link(qemu_session *q)
{
	evo_can_frame f = {EVO_WIRE_CONFIG, 2, {0}};
	evo_wire_put_u16(f.data, 10000);
	if (elf_keyed) /* a robot that has not had a transfer: counter 0 */
		evo_flash_config_make(test_key, test_key_len, 0, 10000, &f);
	qs_queue_frame(q, &f);
}

/* Read up to the firmware's HELLO frame; its names hash, or 0 on failure
 * (with what came instead printed). */
static uint32_t wait_hello(qemu_session *q)
{
	evo_can_frame f;
	char line[512];
	for (;;) {
		int r = qs_next(q, 10.0, &f, line, sizeof line);
		if (r == QS_FRAME && f.id == EVO_WIRE_HELLO && f.len == 8)
			return evo_wire_get_u32(f.data);
		if (r == QS_LOG)
			continue;
		printf("  waiting for HELLO: got %s%s\n",
		       r == QS_TIMEOUT ? "nothing within 10 s"
		       : r == QS_EXIT  ? "the guest's exit"
		       : r == QS_JUNK  ? "the line "
				       : "another frame",
		       r == QS_JUNK ? line : "");
		return 0;
	}
}

/* Start the firmware, check its HELLO names the trace's robot, and give
 * it the patient link: 0, or -1 with a failed check. */
static int start_ready(qemu_session *q, double deadline_s)
{
	if (start(q, elf, deadline_s) != 0) {
		CHECK(0);
		return -1;
	}
	CHECK_EQ_INT(wait_hello(q), trace.names_hash);
	patient_link(q);
	return 0;
}

/* One reply: the actuator frames and the TICKED frame that ends them. */
typedef struct reply {
	int32_t value[64];
	uint32_t got; /* actuator frames received, bit k */
	uint32_t tick;
	uint8_t flags;
} reply;

/* The next reply within timeout_s: 1, or 0 with the reason printed. */
static int read_reply(qemu_session *q, double timeout_s, reply *r)
{
	evo_can_frame f;
	char line[512];
	memset(r, 0, sizeof *r);
	for (;;) {
		int k = qs_next(q, timeout_s, &f, line, sizeof line);
		if (k == QS_LOG)
			continue;
		if (k != QS_FRAME) {
			printf("  waiting for actuator frames: %s %s\n",
			       k == QS_TIMEOUT ? "nothing came"
			       : k == QS_EXIT  ? "the guest stopped"
					       : "junk:",
			       k == QS_JUNK ? line : "");
			return 0;
		}
		if (f.id == EVO_WIRE_TICKED && f.len == 5) {
			r->tick = evo_wire_get_u32(f.data);
			r->flags = f.data[4];
			return 1;
		}
		int a = evo_wire_unpack(EVO_WIRE_ACTUATOR, &f, r->value,
					trace.n_actuators);
		if (a < 0) {
			printf("  unexpected frame id 0x%03x len %u\n", f.id,
			       f.len);
			return 0;
		}
		r->got |= 1u << a;
	}
}

static uint32_t all_actuator_frames(void)
{
	return (1u << evo_wire_frames(trace.n_actuators)) - 1;
}

/* Ticks [from, to) of the trace, up to `window` in flight, the first with
 * every sensor frame and the others with those that changed; every reply
 * must be complete, unflagged, and equal to the trace. Returns the values
 * that differ (the first few printed), or -1 when replies stop. */
static long replay(qemu_session *q, size_t from, size_t to, unsigned window)
{
	size_t sent = from, done = from;
	long differ = 0;
	reply r;
	while (done < to) {
		for (; sent < to && sent - done < window; sent++)
			qs_queue_trace_tick(q, &trace, sent, sent == from);
		if (!read_reply(q, 5.0, &r))
			return -1;
		if (r.tick != trace.tick[done] || r.flags != 0 ||
		    r.got != all_actuator_frames()) {
			printf("  tick %u: reply for tick %u, flags %u, "
			       "frames 0x%x\n",
			       trace.tick[done], r.tick, r.flags, r.got);
			return -1;
		}
		const int32_t *want = trace.actuator + done * trace.n_actuators;
		for (unsigned a = 0; a < trace.n_actuators; a++)
			if (r.value[a] != want[a] && differ++ < 5)
				printf("  tick %u actuator %u: firmware %d, "
				       "trace %d\n",
				       trace.tick[done], a, r.value[a],
				       want[a]);
		done++;
	}
	return differ;
}

/* The two status frames: bad[4], ticks, incomplete, losses. */
typedef struct status {
	unsigned bad[EVO_WIRE_BAD_COUNT];
	uint32_t ticks;
	unsigned incomplete, losses;
} status;

/* The status reply, waiting at most `wait` seconds for each of its
 * frames: the firmware answers once it has read everything queued before
 * the request, which on a slow emulated UART can take a while. */
static int read_status_within(qemu_session *q, status *st, double wait)
{
	evo_can_frame f = {EVO_WIRE_STATUS_REQ, 0, {0}};
	char line[512];
	int got = 0;
	qs_queue_frame(q, &f);
	while (got != 3) {
		int k = qs_next(q, wait, &f, line, sizeof line);
		if (k == QS_LOG)
			continue;
		if (k != QS_FRAME) {
			printf("  no status reply\n");
			return -1;
		}
		if (f.id == EVO_WIRE_STATUS_LINES && f.len == 8) {
			for (unsigned i = 0; i < EVO_WIRE_BAD_COUNT; i++)
				st->bad[i] = evo_wire_get_u16(f.data + 2 * i);
			got |= 1;
		} else if (f.id == EVO_WIRE_STATUS_LINK && f.len == 8) {
			st->ticks = evo_wire_get_u32(f.data);
			st->incomplete = evo_wire_get_u16(f.data + 4);
			st->losses = evo_wire_get_u16(f.data + 6);
			got |= 2;
		}
	}
	return 0;
}

static int read_status(qemu_session *q, status *st)
{
	return read_status_within(q, st, 5.0);
}

/* ---- tests ------------------------------------------------------------ */

/* Acceptance: the whole trace through the firmware, byte for byte. */
TEST(replay_matches_trace)
{
	qemu_session q;
	/* The deadline guards against a hang, not a slow host (each reply
	 * has its own 5 s): the M3's one-byte UART costs a round of QEMU's
	 * main loop per byte, and where system calls are slow the 10,000
	 * ticks took 131 s, past the 100 s this deadline once was. */
	if (start_ready(&q, 600.0) != 0)
		return;
	double t0 = qs_now();
	long differ = replay(&q, 0, trace.n_ticks, 8);
	double dt = qs_now() - t0;
	CHECK_EQ_INT(differ, 0);
	status st;
	memset(&st, 0xff, sizeof st);
	CHECK(read_status(&q, &st) == 0);
	CHECK_EQ_INT(st.ticks, trace.n_ticks);
	CHECK_EQ_INT(st.incomplete, 0);
	CHECK_EQ_INT(st.losses, 0);
	for (unsigned i = 0; i < EVO_WIRE_BAD_COUNT; i++)
		CHECK_EQ_INT(st.bad[i], 0);
	qs_stop(&q);
	if (differ == 0)
		printf("  %s: %zu ticks, %zu actuator values equal to the "
		       "trace's (%.1f s, %.0f ticks/s)\n",
		       machine, trace.n_ticks,
		       trace.n_ticks * trace.n_actuators, dt,
		       (double)trace.n_ticks / dt);
}

/* Sensor frames stop: neutral within the timeout; then the mind goes on. */
TEST(link_loss_goes_neutral_and_resumes)
{
	const unsigned timeout_ms = 200;
	qemu_session q;
	/* The short timeout only for the silence: on a busy host a tick
	 * can take longer than 200 ms, and the robot's clock keeps the
	 * wall clock's time, so the replays around it have the patient
	 * link of the other tests. */
	if (start_ready(&q, 30.0) != 0)
		return;
	CHECK_EQ_INT(replay(&q, 0, 50, 1), 0);
	evo_can_frame f = {EVO_WIRE_CONFIG, 2, {0}};
	evo_wire_put_u16(f.data, timeout_ms);
	qs_queue_frame(&q, &f);

	/* Half a tick, then silence: the half tick must not count later. */
	evo_wire_pack(EVO_WIRE_SENSOR, trace.sensor + 50 * trace.n_sensors,
		      trace.n_sensors, 0, &f);
	qs_queue_frame(&q, &f);
	CHECK(qs_flush(&q) == 0);
	double silent_at = qs_now();
	reply r;
	CHECK(read_reply(&q, 2.0, &r));
	double after = qs_now() - silent_at;
	CHECK_EQ_INT(r.flags, EVO_WIRE_F_NEUTRAL);
	CHECK_EQ_INT(r.tick, trace.tick[49]);
	CHECK_EQ_INT(r.got, all_actuator_frames());
	for (unsigned a = 0; a < trace.n_actuators; a++)
		CHECK_EQ_INT(r.value[a], EVO_Q16_HALF);
	/* Not before the timeout; within it, give or take the host's
	 * scheduling (QEMU's clock follows the host's). */
	CHECK(after >= timeout_ms * 0.9e-3);
	CHECK(after <= timeout_ms * 1e-3 + 0.3);
	printf("  %s: neutral %.0f ms after the last sensor frame (timeout "
	       "%u ms)\n",
	       machine, after * 1e3, timeout_ms);

	/* Frames again: the mind goes on exactly as in the trace. */
	patient_link(&q);
	CHECK_EQ_INT(replay(&q, 50, 100, 1), 0);
	status st;
	memset(&st, 0, sizeof st);
	CHECK(read_status(&q, &st) == 0);
	CHECK_EQ_INT(st.losses, 1);
	CHECK_EQ_INT(st.ticks, 100);
	CHECK_EQ_INT(st.incomplete, 0);
	qs_stop(&q);
}

/* The robot's clock keeps the wall clock's time while the emulator is off
 * the CPU, as a busy host keeps it for tens of milliseconds at a time: the
 * emulator is stopped (SIGSTOP) for 3 s, 100 ms into a 1.5 s link timeout;
 * when it runs again its clock says 3.1 s have passed, and the neutral
 * frames come at once. A clock that counted its millisecond interrupts
 * lost those of the stop: it went neutral 1.4 s after the emulator ran
 * again, and under load every timeout of the robot (the link's, a
 * transfer's) lasted up to three times its length. */
TEST(clock_keeps_time_while_emulator_is_stopped)
{
	const unsigned timeout_ms = 1500;
	qemu_session q;
	if (start_ready(&q, 30.0) != 0)
		return;
	CHECK_EQ_INT(replay(&q, 0, 10, 1), 0);
	evo_can_frame f = {EVO_WIRE_CONFIG, 2, {0}};
	evo_wire_put_u16(f.data, timeout_ms);
	qs_queue_frame(&q, &f);
	CHECK(qs_flush(&q) == 0);
	double silent_at = qs_now();
	struct timespec ms100 = {0, 100000000}, s3 = {3, 0};
	nanosleep(&ms100, NULL);
	CHECK(kill(q.pid, SIGSTOP) == 0);
	nanosleep(&s3, NULL);
	CHECK(kill(q.pid, SIGCONT) == 0);
	double resumed = qs_now();
	reply r;
	CHECK(read_reply(&q, 5.0, &r));
	double after = qs_now() - silent_at, since = qs_now() - resumed;
	CHECK_EQ_INT(r.flags, EVO_WIRE_F_NEUTRAL);
	CHECK_EQ_INT(r.tick, trace.tick[9]);
	/* 0.7 s: twice the longest tick seen on a loaded two-core host;
	 * a lost stop is 1.4 s. */
	CHECK(since <= 0.7);
	printf("  %s: stopped 3 s, 100 ms into a %u ms link timeout: neutral "
	       "%.0f ms after it ran again (%.0f ms after the last sensor "
	       "frame)\n",
	       machine, timeout_ms, since * 1e3, after * 1e3);
	status st;
	memset(&st, 0, sizeof st);
	CHECK(read_status(&q, &st) == 0);
	CHECK_EQ_INT(st.losses, 1);
	qs_stop(&q);
}

/* A tick whose sensor frames are not all there is not stepped. */
TEST(incomplete_tick_is_not_stepped)
{
	qemu_session q;
	if (start_ready(&q, 30.0) != 0)
		return;
	/* Just started, "nothing changed" is not enough: no values yet. */
	evo_can_frame f = {EVO_WIRE_TICK, 8, {0}};
	qs_queue_frame(&q, &f);
	reply r;
	CHECK(read_reply(&q, 5.0, &r));
	CHECK_EQ_INT(r.flags, EVO_WIRE_F_INCOMPLETE);
	for (unsigned a = 0; a < trace.n_actuators; a++)
		CHECK_EQ_INT(r.value[a], EVO_Q16_HALF);
	CHECK_EQ_INT(replay(&q, 0, 10, 1), 0);
	/* A tick whose mask names a frame that did not come. */
	f.id = EVO_WIRE_TICK;
	f.len = 8;
	evo_wire_put_u32(f.data, 77);
	evo_wire_put_u32(f.data + 4, 1u << 3);
	qs_queue_frame(&q, &f);
	CHECK(read_reply(&q, 5.0, &r));
	CHECK_EQ_INT(r.flags, EVO_WIRE_F_INCOMPLETE);
	CHECK_EQ_INT(r.tick, 77);
	/* Tick 10 without its last sensor frame. */
	unsigned frames = evo_wire_frames(trace.n_sensors);
	for (unsigned k = 0; k + 1 < frames; k++) {
		evo_wire_pack(EVO_WIRE_SENSOR,
			      trace.sensor + 10 * trace.n_sensors,
			      trace.n_sensors, k, &f);
		qs_queue_frame(&q, &f);
	}
	f.id = EVO_WIRE_TICK;
	f.len = 4;
	evo_wire_put_u32(f.data, trace.tick[10]);
	qs_queue_frame(&q, &f);
	/* The reply holds tick 9's commands, flagged. */
	CHECK(read_reply(&q, 5.0, &r));
	CHECK_EQ_INT(r.flags, EVO_WIRE_F_INCOMPLETE);
	CHECK_EQ_INT(r.tick, trace.tick[10]);
	CHECK_EQ_INT(r.got, all_actuator_frames());
	for (unsigned a = 0; a < trace.n_actuators; a++)
		CHECK_EQ_INT(r.value[a],
			     trace.actuator[9 * trace.n_actuators + a]);
	/* Had it stepped, tick 10 sent whole would now differ. */
	CHECK_EQ_INT(replay(&q, 10, 20, 1), 0);
	status st;
	memset(&st, 0, sizeof st);
	CHECK(read_status(&q, &st) == 0);
	CHECK_EQ_INT(st.incomplete, 3);
	CHECK_EQ_INT(st.ticks, 20);
	qs_stop(&q);
}

/* Every kind of malformed line, and a stream of garbage. */
TEST(malformed_lines_are_counted_and_ignored)
{
	static const char *const lines[] = {
	    /* overlong: 2 */
	    "t100800000100000001000000000000000000000000000000000\r",
	    "xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx\n",
	    /* syntax: 5 */
	    "t10080000G00000001000\r", /* G is not hex */
	    "T123456780\r",	       /* extended frames: unused */
	    "r1000\r",		       /* remote frames: unused */
	    "O\r",		       /* adapter commands: not here */
	    "\x01\xff\x80 t1008\r",
	    /* bad length: 6 */
	    "t10080000010000\r",       /* DLC 8, 4 bytes */
	    "t10090000010000000100\r", /* DLC 9 */
	    "t100400000100\r",	       /* sensor frame 0 carries 2 values */
	    "t140100\r",	       /* a tick number is 4 bytes */
	    "t1",		       /* too short (ended by the next line) */
	    "\rt1C101\r",	       /* a status request has no data */
	    /* unknown id: 4 */
	    "t7FF0\r", "t1800\r",      /* actuator frames go the other way */
	    "t10A80000010000000100\r", /* sensors 20, 21: Collect has 20 */
	    "t8000\r",		       /* beyond 11 bits */
	};
	const unsigned want[EVO_WIRE_BAD_COUNT] = {2, 5, 6, 4};
	qemu_session q;
	if (start_ready(&q, 30.0) != 0)
		return;
	for (size_t i = 0; i < sizeof lines / sizeof *lines; i++)
		qs_queue(&q, lines[i], strlen(lines[i]));
	status st;
	memset(&st, 0, sizeof st);
	CHECK(read_status(&q, &st) == 0);
	for (unsigned i = 0; i < EVO_WIRE_BAD_COUNT; i++)
		CHECK_EQ_INT(st.bad[i], want[i]);

	/* 64 KB of garbage without a 't' (so no line can be a frame): the
	 * firmware must count what the host's decoder counts. */
	static char junk[65536];
	unsigned model[EVO_WIRE_BAD_COUNT] = {0};
	uint32_t x = 12345;
	evo_slcan_rx rx;
	evo_slcan_rx_init(&rx);
	for (size_t i = 0; i < sizeof junk; i++) {
		x = x * 1103515245u + 12345u;
		char c = (char)(x >> 16);
		junk[i] = c == 't' ? 'T' : c;
	}
	junk[sizeof junk - 1] = '\r'; /* end the last garbage line */
	for (size_t i = 0; i < sizeof junk; i++) {
		evo_can_frame f;
		evo_wire_bad bad;
		if (evo_slcan_rx_byte(&rx, (uint8_t)junk[i], &f, &bad) ==
		    EVO_SLCAN_BAD)
			model[bad]++;
	}
	qs_queue(&q, junk, sizeof junk);
	status st2;
	memset(&st2, 0, sizeof st2);
	/* 64 KB through the M3 board's emulated UART can take longer than
	 * the usual 5 s under load. */
	int rc = read_status_within(&q, &st2, 60.0);
	CHECK_EQ_INT(rc, 0);
	if (rc != 0) {
		qs_stop(&q);
		return;
	}
	unsigned total = 0;
	for (unsigned i = 0; i < EVO_WIRE_BAD_COUNT; i++) {
		CHECK_EQ_INT(st2.bad[i] - st.bad[i], model[i]);
		total += model[i];
	}
	CHECK(total > 100);
	/* Still ticking as the host does. */
	CHECK_EQ_INT(replay(&q, 0, 20, 1), 0);
	printf("  %s: %u garbage lines counted and ignored\n", machine, total);
	qs_stop(&q);
}

/* A firmware ELF with slot holding `image` (len bytes, padded as erased
 * flash) instead of the mind it was built with. 0 or -1. */
static int with_image(const char *name, const void *image, size_t len,
		      char *out, size_t cap)
{
	char bin[512];
	static unsigned char slot[SLOT_BYTES];
	if (len > sizeof slot)
		return -1;
	memset(slot, 0xFF, sizeof slot);
	memcpy(slot, image, len);
	snprintf(bin, sizeof bin, "%s/%s-%s.slot", opt.tmp, machine, name);
	snprintf(out, cap, "%s/%s-%s.elf", opt.tmp, machine, name);
	FILE *f = fopen(bin, "wb");
	if (!f || fwrite(slot, 1, sizeof slot, f) != sizeof slot) {
		if (f)
			fclose(f);
		return -1;
	}
	fclose(f);
	char cmd[2048];
	snprintf(cmd, sizeof cmd, "%s --update-section .mind=%s %s %s",
		 opt.objcopy, bin, elf, out);
	return system(cmd) == 0 ? 0 : -1;
}

static unsigned char *read_all(const char *path, size_t *len)
{
	FILE *f = fopen(path, "rb");
	static unsigned char buf[SLOT_BYTES + 1];
	if (!f)
		return NULL;
	*len = fread(buf, 1, sizeof buf, f);
	fclose(f);
	return *len > 0 && *len <= SLOT_BYTES ? buf : NULL;
}

/* The firmware with `image` must print `reason` and exit with status. */
static void expect_refused(const char *name, const void *image, size_t len,
			   const char *reason, int want_status)
{
	char variant[512], line[512], seen[1024] = "";
	if (with_image(name, image, len, variant, sizeof variant) != 0) {
		test_fail_at(__FILE__, __LINE__, "objcopy --update-section");
		return;
	}
	qemu_session q;
	if (start(&q, variant, 20.0) != 0) {
		CHECK(0);
		return;
	}
	evo_can_frame f;
	int k;
	while ((k = qs_next(&q, 10.0, &f, line, sizeof line)) != QS_EXIT &&
	       k != QS_TIMEOUT)
		if (k == QS_LOG && strstr(line, "refused"))
			snprintf(seen, sizeof seen, "%s", line);
	CHECK(k == QS_EXIT);
	int st = qs_wait_exit(&q, 5.0);
	qs_stop(&q);
	CHECK_CONTAINS(seen, reason);
	CHECK_EQ_INT(st, want_status);
	printf("  %s: %s -> exit %d\n", machine, seen, st);
}

TEST(corrupt_image_is_refused)
{
	size_t len;
	unsigned char *img = read_all(opt.image, &len);
	CHECK(img != NULL);
	if (!img)
		return;
	img[len / 2] ^= 0x10; /* one bit, inside the networks */
	expect_refused("corrupt", img, len,
		       "mind image refused: mind image is corrupt (CRC-32 "
		       "mismatch)",
		       EXIT_IMAGE_CORRUPT);
}

TEST(image_for_other_botdesc_is_refused)
{
	size_t len;
	unsigned char *img = read_all(opt.other_image, &len);
	CHECK(img != NULL);
	if (!img)
		return;
	expect_refused("other", img, len,
		       "mind image refused: mind image was built for other "
		       "sensors, actuators or variables",
		       EXIT_IMAGE_MISMATCH);
}

/* The mind's first network link with a weight far beyond
 * EVO_NET_WEIGHT_MAX, behind a repaired CRC: what a buggy tool could
 * write. Ticking it would overflow the network's sums, so the firmware
 * must refuse it at start (evo_mind_open, EVO_ERR_IMAGE_RANGE). */
TEST(image_with_out_of_range_weight_is_refused)
{
	size_t len;
	unsigned char *img = read_all(opt.image, &len);
	CHECK(img != NULL && len >= sizeof(evo_image_header));
	if (!img || len < sizeof(evo_image_header))
		return;
	evo_image_header h;
	memcpy(&h, img, sizeof h);
	CHECK_EQ_INT(h.length, len);
	if (h.length != len)
		return;
	evo_image_net net = {0};
	unsigned k = 0;
	for (; k < h.n_nets; k++) {
		size_t at = h.off_nets + k * sizeof net;
		if (at + sizeof net > len)
			break;
		memcpy(&net, img + at, sizeof net);
		if (net.n_links > 0)
			break;
	}
	CHECK(k < h.n_nets && net.n_links > 0 &&
	      net.off_links + sizeof(evo_net_link) <= len);
	if (k == h.n_nets || net.off_links + sizeof(evo_net_link) > len)
		return;
	const evo_q16 w = INT32_MAX; /* about 32768.0 */
	memcpy(img + net.off_links + offsetof(evo_net_link, weight), &w,
	       sizeof w);
	uint32_t crc = evo_crc32(0, img + 16, h.length - 16);
	memcpy(img + offsetof(evo_image_header, crc), &crc, sizeof crc);
	expect_refused("range", img, len,
		       "mind image refused: mind image has a network weight "
		       "or bias out of range",
		       EXIT_IMAGE_INVALID);
}

TEST(empty_slot_is_refused)
{
	expect_refused("empty", "", 0,
		       "mind image refused: not a mind image (bad magic)",
		       EXIT_IMAGE_CORRUPT);
}

/* ---- evo flash -------------------------------------------------------- */

/* One run of `evo flash` against the firmware while the driver ticks it.
 * The driver is the bus: evo flash talks to it over cannelloni on the
 * loopback interface, and it passes evo flash's frames to the firmware
 * between two ticks (losing, cutting or damaging one on demand) and the
 * firmware's replies back. The driver plays the world from the old mind's
 * trace until the firmware says it switched, then from the new mind's
 * trace, from its first tick: so every tick checks that the mind the
 * firmware runs is the one it said.
 *
 * Not a pseudo-terminal (slcan-pty:), as it once was: what is written to
 * a terminal reaches its reader only once a kernel worker thread has moved
 * it (flush_to_ldisc), and the reader's poll waits for that worker
 * (n_tty_poll, __flush_work). On a host whose cores are all busy the
 * worker waited for a CPU for up to 4.5 s, evo flash with it, and the
 * robot's 3 s transfer timeout or evo flash's own 1 s wait ran out.
 * A datagram on the loopback interface is delivered by the sender's own
 * system call (docs/firmware.md). */
typedef struct flash_run {
	const char *what; /* evo flash's first argument */
	long cut_at;	  /* frames of the transfer from this one on lost */
	long drop_at;	  /* this frame of the transfer lost */
	long corrupt_at;  /* this frame of the transfer: a bit flipped */
	long corrupt_seg; /* this segment, each time it is sent: a bit
			     flipped (frames sent again do not shift it) */
	const char *wait; /* evo flash --wait MS */
	int record;	  /* keep the transfer's frames (recorded[]) */
	const char *key;  /* evo flash --key */
	/* results */
	int status;	    /* evo flash's exit status */
	char out[4096];	    /* what it printed */
	int switched;	    /* the firmware said DONE */
	uint32_t done_tick; /* the tick it named */
	size_t old_ticks, new_ticks, frames;
	double max_gap; /* longest wait for a tick's reply, s */
} flash_run;

static void flash_run_init(flash_run *fr, const char *what)
{
	memset(fr, 0, sizeof *fr);
	fr->what = what;
	fr->cut_at = fr->drop_at = fr->corrupt_at = fr->corrupt_seg = -1;
}

/* The next reply, passing the firmware's flash replies on to evo flash. */
static int read_reply_passing(qemu_session *q, evo_can *bus, double timeout_s,
			      reply *r, flash_run *fr)
{
	evo_can_frame f;
	char line[512];
	evo_err err;
	memset(r, 0, sizeof *r);
	for (;;) {
		int k = qs_next(q, timeout_s, &f, line, sizeof line);
		if (k == QS_LOG)
			continue;
		if (k != QS_FRAME) {
			printf("  waiting for actuator frames: %s %s\n",
			       k == QS_TIMEOUT ? "nothing came"
			       : k == QS_EXIT  ? "the guest stopped"
					       : "junk:",
			       k == QS_JUNK ? line : "");
			return 0;
		}
		if (f.id == EVO_FLASH_TAG) {
			if (evo_can_send(bus, &f, &err) != 0)
				printf("  to evo flash: %s\n", err.msg);
			continue;
		}
		if (f.id == EVO_FLASH_REPLY) {
			if (f.len == 8 && f.data[0] == EVO_FLASH_DONE) {
				fr->switched = 1;
				fr->done_tick = evo_wire_get_u32(f.data + 4);
			}
			if (evo_can_send(bus, &f, &err) != 0)
				printf("  to evo flash: %s\n", err.msg);
			continue;
		}
		if (f.id == EVO_WIRE_TICKED && f.len == 5) {
			r->tick = evo_wire_get_u32(f.data);
			r->flags = f.data[4];
			return 1;
		}
		int a = evo_wire_unpack(EVO_WIRE_ACTUATOR, &f, r->value,
					trace.n_actuators);
		if (a < 0) {
			printf("  unexpected frame id 0x%03x len %u\n", f.id,
			       f.len);
			return 0;
		}
		r->got |= 1u << a;
	}
}

/* The frames of a whole transfer as a recorder on the bus kept them (the
 * first flash test's), for the test that plays them again. */
static evo_can_frame recorded[1024];
static size_t n_recorded;

/* A UDP port of the loopback interface no socket has now: 0 if none. */
static unsigned free_udp_port(void)
{
	int fd = socket(AF_INET, SOCK_DGRAM, 0);
	if (fd < 0)
		return 0;
	struct sockaddr_in a;
	memset(&a, 0, sizeof a);
	a.sin_family = AF_INET;
	a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
	socklen_t n = sizeof a;
	unsigned port = 0;
	if (bind(fd, (struct sockaddr *)&a, sizeof a) == 0 &&
	    getsockname(fd, (struct sockaddr *)&a, &n) == 0)
		port = ntohs(a.sin_port);
	close(fd);
	return port;
}

/* Start evo flash on the bus url, its output to a file. */
static pid_t spawn_flash(const flash_run *fr, const char *url, char *outpath,
			 size_t cap)
{
	/* a new file for every run (small; make clean removes them):
	 * truncating the last one's waits for its pages' writeback, which a
	 * busy disk held back past the whole test, evo flash not started */
	static unsigned runs;
	snprintf(outpath, cap, "%s/%s-flash-%ld-%u.out", opt.tmp, machine,
		 (long)getpid(), runs++);
	fflush(stdout);
	pid_t pid = fork();
	if (pid == 0) {
		int fd = open(outpath, O_WRONLY | O_CREAT | O_EXCL, 0644);
		if (fd < 0)
			_exit(127);
		dup2(fd, 1);
		dup2(fd, 2);
		const char *argv[12] = {opt.evo, "flash", fr->what, "--can",
					url};
		int n = 5;
		if (fr->key) {
			argv[n++] = "--key";
			argv[n++] = fr->key;
		}
		if (fr->wait) {
			argv[n++] = "--wait";
			argv[n++] = fr->wait;
		}
		argv[n] = NULL;
		execv(opt.evo, (char *const *)argv);
		_exit(127);
	}
	return pid;
}

/* Tick the firmware through one evo flash, and 40 ticks after it ended.
 * Returns the actuator values that differ from the traces, or -1 when
 * the run could not go on (printed). */
static long flash_while_ticking(flash_run *fr)
{
	qemu_session q;
	if (start_ready(&q, 120.0) != 0)
		return -1;
	evo_err err;
	unsigned mine = free_udp_port(), its = free_udp_port();
	for (int i = 0; i < 5 && its == mine; i++)
		its = free_udp_port();
	char url[128], its_url[128];
	snprintf(url, sizeof url, "cannelloni:127.0.0.1:%u?local=%u", its,
		 mine);
	snprintf(its_url, sizeof its_url, "cannelloni:127.0.0.1:%u?local=%u",
		 mine, its);
	evo_can *bus =
	    mine && its && mine != its ? evo_can_open(url, &err) : NULL;
	if (!bus) {
		printf("  %s\n", mine && its && mine != its
				     ? err.msg
				     : "no free UDP port on 127.0.0.1");
		qs_stop(&q);
		return -1;
	}
	char outpath[600];
	pid_t pid = spawn_flash(fr, its_url, outpath, sizeof outpath);
	long differ = 0, after = 0;
	int exited = 0, st = 0;
	reply r;
	while (after < 40) {
		/* What evo flash sent, to the firmware, between two ticks. */
		evo_can_frame f;
		int end_sent = 0;
		while (evo_can_recv(bus, 0, &f, &err) == 1) {
			if (f.id < EVO_FLASH_BEGIN || f.id > EVO_FLASH_AUTH ||
			    f.id == EVO_FLASH_REPLY)
				continue;
			long k = (long)fr->frames++;
			if (fr->record && n_recorded < 1024)
				recorded[n_recorded++] = f;
			if ((fr->cut_at >= 0 && k >= fr->cut_at) ||
			    k == fr->drop_at)
				continue;
			if (k == fr->corrupt_at && f.len > 1)
				f.data[f.len - 1] ^= 0x10;
			if (fr->corrupt_seg >= 0 && f.id == EVO_FLASH_DATA &&
			    f.data[0] == (uint8_t)fr->corrupt_seg && f.len > 1)
				f.data[f.len - 1] ^= 0x10;
			qs_queue_frame(&q, &f);
			end_sent |= f.id == EVO_FLASH_END;
		}
		/* The answer to an END before the next tick: the world the
		 * driver plays must be the one of the mind that runs. */
		while (end_sent && !fr->switched) {
			evo_can_frame g;
			char line[512];
			int k = qs_next(&q, 5.0, &g, line, sizeof line);
			if (k == QS_LOG)
				continue;
			if (k == QS_FRAME && g.id == EVO_FLASH_TAG) {
				evo_can_send(bus, &g, &err);
				continue;
			}
			if (k != QS_FRAME || g.id != EVO_FLASH_REPLY) {
				printf("  no answer to END\n");
				differ = -1;
				goto out;
			}
			if (g.data[0] == EVO_FLASH_DONE) {
				fr->switched = 1;
				fr->done_tick = evo_wire_get_u32(g.data + 4);
			}
			evo_can_send(bus, &g, &err);
			if (g.data[0] == EVO_FLASH_DONE ||
			    g.data[0] == EVO_FLASH_REFUSED)
				break;
		}
		if (!exited && waitpid(pid, &st, WNOHANG) == pid)
			exited = 1;
		if (exited)
			after++;
		const trace_file *t = fr->switched ? &new_trace : &trace;
		size_t i = fr->switched ? fr->new_ticks : fr->old_ticks;
		if (i >= t->n_ticks || qs_now() > q.deadline) {
			char wchan[64] = "?", path[64];
			snprintf(path, sizeof path, "/proc/%d/wchan", (int)pid);
			FILE *w = fopen(path, "r");
			if (w) {
				size_t n = fread(wchan, 1, sizeof wchan - 1, w);
				wchan[n] = 0;
				fclose(w);
			}
			/* where it waits, and the kernel's stack of it: on a
			 * pseudo-terminal it once waited for the kernel's tty
			 * worker (see above flash_run) */
			printf("  evo flash still running after %zu ticks, %zu "
			       "frames of the transfer; waiting in %s\n",
			       fr->old_ticks + fr->new_ticks, fr->frames,
			       wchan);
			snprintf(path, sizeof path, "/proc/%d/stack", (int)pid);
			w = fopen(path, "r");
			if (w) {
				char line[256];
				while (fgets(line, sizeof line, w))
					printf("    %s", line);
				fclose(w);
			}
			differ = -1;
			goto out;
		}
		qs_queue_trace_tick(&q, t, i, i == 0);
		double t0 = qs_now();
		if (!read_reply_passing(&q, bus, 5.0, &r, fr)) {
			differ = -1;
			goto out;
		}
		if (qs_now() - t0 > fr->max_gap)
			fr->max_gap = qs_now() - t0;
		if (r.tick != t->tick[i] || r.flags != 0 ||
		    r.got != all_actuator_frames()) {
			printf("  tick %u of the %s trace: reply for tick %u, "
			       "flags %u, frames 0x%x\n",
			       t->tick[i], fr->switched ? "new" : "old", r.tick,
			       r.flags, r.got);
			differ = -1;
			goto out;
		}
		const int32_t *want = t->actuator + i * t->n_actuators;
		for (unsigned a = 0; a < t->n_actuators; a++)
			if (r.value[a] != want[a] && differ++ < 5)
				printf("  %s tick %u actuator %u: firmware %d, "
				       "trace %d\n",
				       fr->switched ? "new" : "old", t->tick[i],
				       a, r.value[a], want[a]);
		if (fr->switched)
			fr->new_ticks++;
		else
			fr->old_ticks++;
	}
	/* Every tick stepped, none incomplete, no link lost, no line
	 * refused: the transfer took nothing from the ticks. */
	status sts;
	memset(&sts, 0xff, sizeof sts);
	CHECK(read_status(&q, &sts) == 0);
	CHECK_EQ_INT(sts.ticks, fr->old_ticks + fr->new_ticks);
	CHECK_EQ_INT(sts.incomplete, 0);
	CHECK_EQ_INT(sts.losses, 0);
	for (unsigned b = 0; b < EVO_WIRE_BAD_COUNT; b++)
		CHECK_EQ_INT(sts.bad[b], 0);
out:
	if (!exited) {
		kill(pid, SIGKILL);
		waitpid(pid, &st, 0);
	}
	fr->status = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
	FILE *o = fopen(outpath, "r");
	size_t n = o ? fread(fr->out, 1, sizeof fr->out - 1, o) : 0;
	fr->out[n] = 0;
	if (o)
		fclose(o);
	evo_can_close(bus);
	qs_stop(&q);
	return differ;
}

/* A frame of the transfer, chosen from the run's seed: [lo, hi]. */
static long seeded_frame(unsigned salt, long lo, long hi)
{
	uint64_t x = (opt.seed + salt) * 0x9E3779B97F4A7C15u;
	x ^= x >> 29;
	return lo + (long)(x % (uint64_t)(hi - lo + 1));
}

/* Frames of a whole transfer of the new mind (BEGIN, segments, END), as
 * the first flash test counted them. */
static long transfer_frames = 100;

/* Acceptance: the new mind from the switch on, the old one before. */
TEST(flash_switches_between_ticks)
{
	flash_run fr;
	flash_run_init(&fr, opt.new_mind);
	fr.record = 1;
	n_recorded = 0;
	long differ = flash_while_ticking(&fr);
	CHECK_EQ_INT(differ, 0);
	CHECK_EQ_INT(fr.status, 0);
	CHECK(fr.switched);
	CHECK(fr.old_ticks > 0 && fr.new_ticks >= 40);
	CHECK_EQ_INT(fr.done_tick, trace.tick[fr.old_ticks - 1]);
	char want[128];
	snprintf(want, sizeof want, "from the tick after %u (", fr.done_tick);
	CHECK_CONTAINS(fr.out, want);
	CHECK_CONTAINS(fr.out, "0 segments sent again");
	/* The frames of a transfer with none sent again, as evo flash
	 * counts them: a cut or a damage chosen among them falls inside
	 * the next transfers even if this one had to send some again. */
	unsigned sent, again;
	const char *said = strstr(fr.out, "from the tick after");
	if (fr.switched && said &&
	    sscanf(said, "from the tick after %*u (%u frames sent, %u segments",
		   &sent, &again) == 2 &&
	    sent > again)
		transfer_frames = (long)(sent - again);
	printf("  %s: switched after %zu ticks of the old mind; %zu of the new "
	       "mind's equal its trace; %zu frames of the transfer; longest "
	       "tick %.0f ms\n",
	       machine, fr.old_ticks, fr.new_ticks, fr.frames,
	       fr.max_gap * 1e3);
	if (differ != 0 || fr.status != 0)
		printf("  evo flash said:\n%s", fr.out);
}

TEST(flash_lost_frame_is_sent_again)
{
	flash_run fr;
	flash_run_init(&fr, opt.new_mind);
	fr.drop_at = seeded_frame(1, 1, transfer_frames - 2);
	long differ = flash_while_ticking(&fr);
	CHECK_EQ_INT(differ, 0);
	CHECK_EQ_INT(fr.status, 0);
	CHECK(fr.switched && fr.new_ticks >= 40);
	CHECK(strstr(fr.out, " 0 segments sent again") == NULL);
	printf("  %s: frame %ld lost: %s", machine, fr.drop_at,
	       strstr(fr.out, "the robot runs")
		   ? strstr(fr.out, "the robot runs")
		   : fr.out);
}

/* The refusals: the old mind ticks on, and evo flash says why. */
static void expect_flash_refused(flash_run *fr, const char *why)
{
	long differ = flash_while_ticking(fr);
	CHECK_EQ_INT(differ, 0);
	CHECK_EQ_INT(fr->status, 1);
	CHECK(!fr->switched);
	CHECK_EQ_INT(fr->new_ticks, 0);
	CHECK_CONTAINS(fr->out, why);
	CHECK_CONTAINS(fr->out, "keeps running the mind it had");
	const char *line = strstr(fr->out, "evo flash: the robot");
	printf("  %s: %ld ticks of the old mind, none missed: %s", machine,
	       (long)fr->old_ticks, line ? line : fr->out);
}

TEST(flash_cut_at_random_frame_keeps_old_mind)
{
	flash_run fr;
	flash_run_init(&fr, opt.new_mind);
	/* BEGIN gets through; anything from the first segment to END may
	 * be the first frame lost. */
	fr.cut_at = seeded_frame(2, 1, transfer_frames - 1);
	/* evo flash waits longer than the robot's 3 s: a busy host's guest
	 * clock runs behind, and the robot's refusal must come first */
	fr.wait = "3000";
	printf("  %s: the transfer cut from frame %ld on (seed %lu)\n", machine,
	       fr.cut_at, opt.seed);
	expect_flash_refused(&fr, "the transfer stopped: the robot heard "
				  "nothing of it for its transfer timeout "
				  "(3000 ms)");
}

TEST(flash_corrupted_segment_keeps_old_mind)
{
	flash_run fr;
	flash_run_init(&fr, opt.new_mind);
	/* a segment (frame k is segment k - 1), flipped each time it is sent,
	 * so that segments sent again after a wait do not move it */
	fr.corrupt_seg = seeded_frame(3, 1, transfer_frames - 2) - 1;
	printf("  %s: a bit flipped in segment %ld (seed %lu)\n", machine,
	       fr.corrupt_seg, opt.seed);
	expect_flash_refused(&fr, "the image arrived corrupted: the "
				  "transfer's CRC-32 does not match");
}

TEST(flash_other_robots_image_keeps_old_mind)
{
	flash_run fr;
	flash_run_init(&fr, opt.other_mind);
	size_t len;
	unsigned char *img = read_all(opt.other_image, &len);
	CHECK(img != NULL && len >= 20);
	if (!img || len < 20)
		return;
	char why[300];
	snprintf(why, sizeof why,
		 "the image was built for another robot: other sensors, "
		 "actuators or variables (the image's names hash %08x, the "
		 "robot's %08x)",
		 evo_wire_get_u32(img + 16), trace.names_hash);
	expect_flash_refused(&fr, why);
	CHECK_EQ_INT(fr.frames, 1); /* BEGIN only: refused before a segment */
}

/* Issue 27, item 13: the transfer the first flash test sent (counter 1,
 * to a robot that had none), recorded and played again to a robot whose
 * slot says its last transfer had counter 5, as a robot has after a reset:
 * refused as stale, and the mind it runs goes on, equal to its trace. */
TEST(flash_replayed_transfer_is_refused)
{
	CHECK(n_recorded > 2);
	if (n_recorded <= 2) {
		printf("  no transfer was recorded (flash_switches_between_ticks "
		       "must run first)\n");
		return;
	}
	size_t len;
	unsigned char *img = read_all(opt.image, &len);
	CHECK(img != NULL && len + 4 <= SLOT_BYTES);
	if (!img || len + 4 > SLOT_BYTES)
		return;
	static unsigned char slot0[SLOT_BYTES];
	memcpy(slot0, img, len);
	evo_wire_put_u32(slot0 + len, 5);
	char variant[512], line[512], banner[1024] = "";
	if (with_image("counter5", slot0, len + 4, variant, sizeof variant) !=
	    0) {
		test_fail_at(__FILE__, __LINE__, "objcopy --update-section");
		return;
	}
	qemu_session q;
	if (start(&q, variant, 120.0) != 0) {
		CHECK(0);
		return;
	}
	evo_can_frame f;
	int k;
	while ((k = qs_next(&q, 10.0, &f, line, sizeof line)) == QS_LOG)
		if (strstr(line, "# mind "))
			snprintf(banner, sizeof banner, "%s", line);
	CHECK(k == QS_FRAME && f.id == EVO_WIRE_HELLO);
	CHECK_CONTAINS(banner, "; transfer counter 5");
	patient_link(&q);
	for (size_t i = 0; i < n_recorded; i++)
		qs_queue_frame(&q, &recorded[i]);
	CHECK(qs_flush(&q) == 0);
	int ready = 0, done = 0, refused = -1;
	uint32_t detail = 0, robot = ~0u;
	while (refused < 0 && !done) {
		k = qs_next(&q, 20.0, &f, line, sizeof line);
		if (k == QS_LOG)
			continue;
		if (k != QS_FRAME) {
			printf("  waiting for the refusal: %s\n",
			       k == QS_TIMEOUT ? "nothing came" : line);
			break;
		}
		if (f.id != EVO_FLASH_REPLY || f.len != 8)
			continue;
		if (f.data[0] == EVO_FLASH_READY) {
			ready++;
			robot = evo_wire_get_u32(f.data + 4);
		}
		done |= f.data[0] == EVO_FLASH_DONE;
		if (f.data[0] == EVO_FLASH_REFUSED) {
			refused = f.data[1];
			detail = evo_wire_get_u32(f.data + 4);
		}
	}
	CHECK_EQ_INT(ready, 1);
	CHECK_EQ_INT(robot, 5); /* READY says the robot's counter */
	CHECK_EQ_INT(done, 0);
	CHECK_EQ_INT(refused, EVO_FLASH_ERR_STALE);
	CHECK_EQ_INT(detail, 5);
	/* the mind it had runs on */
	CHECK_EQ_INT(replay(&q, 0, 40, 1), 0);
	printf("  %s: %zu frames played again: refused as stale (the "
	       "robot's counter %u)\n",
	       machine, n_recorded, detail);
	qs_stop(&q);
}

/* Issue 27, item 13: a CONFIG from any node asking for the longest link
 * timeout (65,535 ms) gets the firmware's bound, 10,000 ms: the actuators
 * go neutral 10 s (of the guest's clock) after the ticks stop, not a
 * minute later. */
TEST(flash_config_cannot_hold_the_link_past_its_bound)
{
	qemu_session q;
	if (start_ready(&q, 120.0) != 0)
		return;
	evo_can_frame f = {EVO_WIRE_CONFIG, 2, {0xFF, 0xFF}};
	qs_queue_frame(&q, &f);
	CHECK_EQ_INT(replay(&q, 0, 5, 1), 0);
	double silent_at = qs_now();
	reply r;
	CHECK(read_reply(&q, 60.0, &r));
	double after = qs_now() - silent_at;
	CHECK_EQ_INT(r.flags, EVO_WIRE_F_NEUTRAL);
	/* the guest's clock runs behind the host's on a busy machine (10 s
	 * of it took 17 s with both cores busy): well short of 65.5 s */
	CHECK(after > 9.0 && after < 45.0);
	printf("  %s: CONFIG 65535 ms: neutral %.1f s after the last tick\n",
	       machine, after);
	qs_stop(&q);
}

/* Issue 27, item 13: a firmware built with a key (make firmware
 * FW_KEY=FILE; here the public test key) takes a transfer only from evo
 * flash --key FILE: without it evo flash does not send, and the robot's
 * mind goes on; with it the new mind runs from the switch on. */
TEST(flash_keyed_robot_takes_only_its_key)
{
	const char *keyed = NULL;
	for (unsigned i = 0; i < opt.n_keyed; i++)
		if (strcmp(opt.keyed_machine[i], machine) == 0)
			keyed = opt.keyed_elf[i];
	CHECK(keyed != NULL && test_key_len > 0);
	if (!keyed || !test_key_len)
		return;
	const char *plain = elf;
	elf = keyed;
	elf_keyed = 1;
	flash_run fr;
	flash_run_init(&fr, opt.new_mind);
	long differ = flash_while_ticking(&fr);
	CHECK_EQ_INT(differ, 0);
	CHECK_EQ_INT(fr.status, 1);
	CHECK(!fr.switched);
	CHECK_EQ_INT(fr.frames, 1); /* BEGIN only */
	CHECK_CONTAINS(fr.out, "evo flash: not sent: the robot takes only "
			       "transfers sent with its key");
	flash_run_init(&fr, opt.new_mind);
	fr.key = opt.key_path;
	differ = flash_while_ticking(&fr);
	CHECK_EQ_INT(differ, 0);
	CHECK_EQ_INT(fr.status, 0);
	CHECK(fr.switched && fr.new_ticks >= 40);
	CHECK_CONTAINS(fr.out, "the robot runs mind");
	if (differ != 0 || fr.status != 0)
		printf("  evo flash said:\n%s", fr.out);
	printf("  %s: keyed firmware: refused without the key, switched "
	       "with it after %zu ticks; %zu frames\n",
	       machine, fr.old_ticks, fr.frames);
	elf = plain;
	elf_keyed = 0;
}

/* ---- main ------------------------------------------------------------- */

/* FW_TEST_ONLY=WORD runs only the tests whose names contain WORD (e.g.
 * flash), when working on one part. */
#define RUN_FW(name)                                                           \
	do {                                                                   \
		const char *only_ = getenv("FW_TEST_ONLY");                    \
		if (!only_ || strstr(#name, only_))                            \
			RUN(name);                                             \
	} while (0)

static int usage(void)
{
	fprintf(stderr,
		"usage: firmware_test --qemu QEMU --objcopy OBJCOPY --trace "
		"TRACE --image MIND.bin --other-image OTHER.bin --tmp DIR "
		"--evo EVO --new-mind DIR --new-trace TRACE --other-mind DIR "
		"--seed N --firmware MACHINE=ELF ... [--key KEYFILE --keyed "
		"MACHINE=ELF ...]\n");
	return 2;
}

int main(int argc, char **argv)
{
	for (int i = 1; i + 1 < argc; i += 2) {
		const char *a = argv[i], *v = argv[i + 1];
		if (strcmp(a, "--qemu") == 0)
			opt.qemu = v;
		else if (strcmp(a, "--objcopy") == 0)
			opt.objcopy = v;
		else if (strcmp(a, "--trace") == 0)
			opt.trace_path = v;
		else if (strcmp(a, "--image") == 0)
			opt.image = v;
		else if (strcmp(a, "--other-image") == 0)
			opt.other_image = v;
		else if (strcmp(a, "--tmp") == 0)
			opt.tmp = v;
		else if (strcmp(a, "--evo") == 0)
			opt.evo = v;
		else if (strcmp(a, "--new-mind") == 0)
			opt.new_mind = v;
		else if (strcmp(a, "--new-trace") == 0)
			opt.new_trace = v;
		else if (strcmp(a, "--other-mind") == 0)
			opt.other_mind = v;
		else if (strcmp(a, "--seed") == 0)
			opt.seed = strtoul(v, NULL, 10);
		else if (strcmp(a, "--key") == 0)
			opt.key_path = v;
		else if (strcmp(a, "--keyed") == 0 && strchr(v, '=') &&
			 opt.n_keyed < 4) {
			char *eq = strchr(v, '=');
			opt.keyed_machine[opt.n_keyed] =
			    strndup(v, (size_t)(eq - v));
			opt.keyed_elf[opt.n_keyed++] = eq + 1;
		}
		else if (strcmp(a, "--firmware") == 0 && strchr(v, '=') &&
			 opt.n_fw < 4) {
			char *eq = strchr(v, '=');
			opt.machine[opt.n_fw] = strndup(v, (size_t)(eq - v));
			opt.elf[opt.n_fw++] = eq + 1;
		} else
			return usage();
	}
	if ((argc - 1) % 2 || !opt.qemu || !opt.objcopy || !opt.trace_path ||
	    !opt.image || !opt.other_image || !opt.tmp || !opt.n_fw ||
	    !opt.evo || !opt.new_mind || !opt.new_trace || !opt.other_mind)
		return usage();
	mkdir(opt.tmp, 0755);
	char err[512];
	if (opt.key_path) {
		/* hex digits, as evo flash reads them */
		FILE *kf = fopen(opt.key_path, "r");
		unsigned v;
		while (kf && test_key_len < sizeof test_key &&
		       fscanf(kf, "%2x", &v) == 1)
			test_key[test_key_len++] = (uint8_t)v;
		if (kf)
			fclose(kf);
		if (test_key_len < EVO_FLASH_KEY_MIN) {
			printf("--key %s: not a key\n", opt.key_path);
			return 1;
		}
	}
	if (trace_load(opt.trace_path, &trace, err, sizeof err) != 0) {
		printf("%s\n", err);
		return 1;
	}
	printf("trace %s: mind %s, %zu ticks, %u sensors, %u actuators\n",
	       opt.trace_path, trace.mind, trace.n_ticks, trace.n_sensors,
	       trace.n_actuators);
	if (trace.n_ticks < 100) {
		printf("the trace needs at least 100 ticks\n");
		return 1;
	}
	if (trace_load(opt.new_trace, &new_trace, err, sizeof err) != 0) {
		printf("%s\n", err);
		return 1;
	}
	printf("new mind %s: trace %s, %zu ticks; flash tests' seed %lu\n",
	       opt.new_mind, opt.new_trace, new_trace.n_ticks, opt.seed);
	if (new_trace.names_hash != trace.names_hash ||
	    new_trace.n_actuators != trace.n_actuators) {
		printf("the new mind's trace is for another robot\n");
		return 1;
	}
	/* One process per firmware, run side by side: QEMU's emulated UART
	 * is the slow part, and each core's tests are independent. Their
	 * reports are printed in order once all are done. */
	pid_t pid[4];
	char log[4][600];
	for (unsigned i = 0; i < opt.n_fw; i++) {
		snprintf(log[i], sizeof log[i], "%s/%s.log", opt.tmp,
			 opt.machine[i]);
		fflush(stdout);
		pid[i] = fork();
		if (pid[i] < 0) {
			perror("fork");
			return 1;
		}
		if (pid[i] == 0) {
			if (!freopen(log[i], "w", stdout))
				_exit(1);
			machine = opt.machine[i];
			elf = opt.elf[i];
			printf("== %s: %s\n", machine, elf);
			RUN_FW(replay_matches_trace);
			RUN_FW(link_loss_goes_neutral_and_resumes);
			RUN_FW(clock_keeps_time_while_emulator_is_stopped);
			RUN_FW(incomplete_tick_is_not_stepped);
			RUN_FW(malformed_lines_are_counted_and_ignored);
			RUN_FW(corrupt_image_is_refused);
			RUN_FW(image_for_other_botdesc_is_refused);
			RUN_FW(image_with_out_of_range_weight_is_refused);
			RUN_FW(empty_slot_is_refused);
			RUN_FW(flash_switches_between_ticks);
			RUN_FW(flash_lost_frame_is_sent_again);
			RUN_FW(flash_cut_at_random_frame_keeps_old_mind);
			RUN_FW(flash_corrupted_segment_keeps_old_mind);
			RUN_FW(flash_other_robots_image_keeps_old_mind);
			RUN_FW(flash_replayed_transfer_is_refused);
			RUN_FW(flash_config_cannot_hold_the_link_past_its_bound);
			RUN_FW(flash_keyed_robot_takes_only_its_key);
			test_summary();
			fflush(stdout);
			_exit(0);
		}
	}
	for (unsigned i = 0; i < opt.n_fw; i++) {
		int st;
		char line[1024];
		unsigned p = 0, f = 0;
		waitpid(pid[i], &st, 0);
		FILE *in = fopen(log[i], "r");
		while (in && fgets(line, sizeof line, in)) {
			if (sscanf(line, "%u passed, %u failed", &p, &f) == 2)
				continue;
			fputs(line, stdout);
		}
		if (in)
			fclose(in);
		if (!WIFEXITED(st) || WEXITSTATUS(st) != 0 || p + f == 0) {
			printf("FAIL %s: the tests stopped (status %d)\n",
			       opt.machine[i], st);
			f++;
		}
		test_passed_count += (int)p;
		test_failed_count += (int)f;
	}
	trace_free(&trace);
	trace_free(&new_trace);
	return test_summary();
}
