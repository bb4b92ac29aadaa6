/* evo's wire: CAN frames that carry a mind's sensor and actuator values,
 * and slcan (Lawicel ASCII) lines that carry CAN frames over a serial line.
 *
 * Portable C11 and freestanding (no libc, no allocation), so the same code
 * decodes frames on the firmware and builds and checks them on the host.
 * docs/wire.md is the reference for the layout; this header is the API. */
#ifndef EVO_WIRE_H
#define EVO_WIRE_H

#include <stddef.h>
#include <stdint.h>

#include "evo/fixed.h"

/* A classic CAN data frame with an 11-bit (standard) id. */
typedef struct evo_can_frame {
	uint16_t id;	 /* 0 .. 0x7FF */
	uint8_t len;	 /* DLC, 0 .. 8 */
	uint8_t data[8]; /* len bytes used */
} evo_can_frame;

/* ---- the frame layout (docs/wire.md) -------------------------------- */

#define EVO_WIRE_VERSION 1u

/* host -> robot: sensor frame k carries sensors 2k and 2k+1 as Q16,
 * little-endian int32; DLC 8, or 4 for a last frame with one value. */
#define EVO_WIRE_SENSOR 0x100u
#define EVO_WIRE_SENSOR_FRAMES 64u /* 0x100 .. 0x13F: 128 sensors */
/* host -> robot: end of a tick's sensor frames: tick number (u32), echoed
 * in the robot's EVO_WIRE_TICKED. DLC 4: every sensor frame was sent this
 * tick. DLC 8: then a mask (u32) of the frames sent, bit k for frame k;
 * the others keep their last values (for at most 32 sensor frames). */
#define EVO_WIRE_TICK 0x140u
/* robot -> host: actuator frame k carries actuators 2k and 2k+1, packed
 * as sensors are. */
#define EVO_WIRE_ACTUATOR 0x180u
#define EVO_WIRE_ACTUATOR_FRAMES 32u /* 0x180 .. 0x19F: 64 actuators */
/* robot -> host: end of a tick's actuator frames; DLC 5: tick number
 * (u32), flags (u8, EVO_WIRE_F_*). */
#define EVO_WIRE_TICKED 0x1C0u
/* host -> robot, DLC 0: ask for the two status frames below. */
#define EVO_WIRE_STATUS_REQ 0x1C1u
/* robot -> host, DLC 8: lines refused (u16 each, saturating): overlong,
 * syntax, bad length, unknown id (EVO_WIRE_BAD_*). */
#define EVO_WIRE_STATUS_LINES 0x1C2u
/* robot -> host, DLC 8: ticks stepped (u32), incomplete ticks (u16),
 * link losses (u16). */
#define EVO_WIRE_STATUS_LINK 0x1C3u
/* host -> robot, DLC 2: link timeout in milliseconds (u16, 0 means 1). */
#define EVO_WIRE_CONFIG 0x1C4u
/* robot -> host at start, DLC 8: names hash (u32), sensors (u8),
 * actuators (u8), variables (u8), wire version (u8). */
#define EVO_WIRE_HELLO 0x1C5u

/* ---- a robot's body and the mind on the host (DEMOREMOTE over CAN) ---
 * In a DEMOREMOTE task over CAN, evo runs the mind on the host and takes
 * the firmware's place: the robot's body (its sensor and motor nodes, or
 * `evo serve --can`) sends the sensor frames and TICKs above and takes
 * the actuator frames and TICKEDs. These frames carry what a remote
 * robot's LCM hello and control messages carry (docs/wire.md). The
 * firmware does not use them. */
/* body -> mind, DLC 8: the body's names hash (evo_names_hash of its
 * sensor and actuator names in order, no variables; 0: not given),
 * sensors (u8), actuators (u8), its tick period in units of 0.1 ms
 * (u16). Sent at start and in answer to each HELLO. */
#define EVO_WIRE_BODY 0x1C6u
/* mind -> body, DLC 8: episode (u32) starts now, from tick 0; then the
 * CRC-32 of the 16 bytes of the two seed frames sent before it. */
#define EVO_WIRE_RESET 0x1C7u
/* mind -> body, DLC 8, before a RESET: the episode's layout seed and
 * seed (u64 each), as a remote simulator gets them. */
#define EVO_WIRE_LAYOUT_SEED 0x1C8u
#define EVO_WIRE_SEED 0x1C9u
/* mind -> body, DLC 4: episode (u32) is over: every actuator neutral,
 * no more ticks until a RESET. */
#define EVO_WIRE_STOP 0x1CAu
/* body -> mind, DLC 8: the episode's reward so far, as of the next TICK
 * (an IEEE 754 double); optional. */
#define EVO_WIRE_REWARD 0x1CBu
/* body -> mind, DLC 4: the episode ended after this many ticks (u32);
 * the last REWARD is the episode's. */
#define EVO_WIRE_DONE 0x1CCu

/* EVO_WIRE_TICKED flags. */
#define EVO_WIRE_F_NEUTRAL 0x01u    /* link lost: actuators set to 0.5 */
#define EVO_WIRE_F_INCOMPLETE 0x02u /* sensor frames missing: not stepped,
				       the last commands held */

/* Reasons a received line or frame is refused; each has a counter. */
typedef enum evo_wire_bad {
	EVO_WIRE_BAD_OVERLONG = 0, /* line longer than EVO_SLCAN_LINE_MAX */
	EVO_WIRE_BAD_SYNTAX,	   /* not a 't' line, or a digit not hex */
	EVO_WIRE_BAD_LENGTH,	   /* DLC over 8, data digits not 2*DLC,
				      or a DLC the id does not take */
	EVO_WIRE_BAD_ID,	   /* an id the layout does not use here */
	EVO_WIRE_BAD_COUNT
} evo_wire_bad;

/* Frames needed for n values, two per frame. */
static inline unsigned evo_wire_frames(unsigned n)
{
	return (n + 1u) / 2u;
}

/* Little-endian fields. */
static inline void evo_wire_put_u32(uint8_t *p, uint32_t v)
{
	p[0] = (uint8_t)v;
	p[1] = (uint8_t)(v >> 8);
	p[2] = (uint8_t)(v >> 16);
	p[3] = (uint8_t)(v >> 24);
}

static inline uint32_t evo_wire_get_u32(const uint8_t *p)
{
	return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 |
	       (uint32_t)p[3] << 24;
}

static inline void evo_wire_put_u16(uint8_t *p, uint16_t v)
{
	p[0] = (uint8_t)v;
	p[1] = (uint8_t)(v >> 8);
}

static inline uint16_t evo_wire_get_u16(const uint8_t *p)
{
	return (uint16_t)(p[0] | p[1] << 8);
}

/* Frame k of n values (k < evo_wire_frames(n)), with id base + k. */
void evo_wire_pack(uint16_t base, const evo_q16 *values, unsigned n,
		   unsigned k, evo_can_frame *f);

/* Store the values of a frame packed by evo_wire_pack into values (n
 * of them). Returns the frame's index k, or -1 - EVO_WIRE_BAD_ID when
 * the id is not base + k for a k < evo_wire_frames(n), or
 * -1 - EVO_WIRE_BAD_LENGTH when its DLC is not the one frame k has. */
int evo_wire_unpack(uint16_t base, const evo_can_frame *f, evo_q16 *values,
		    unsigned n);

/* ---- slcan ----------------------------------------------------------- */

/* Longest line accepted, without its end: "t" + 3 id digits + 1 DLC digit
 * + 16 data digits. */
#define EVO_SLCAN_LINE_MAX 21u

/* What a received byte completed. */
typedef enum evo_slcan_result {
	EVO_SLCAN_MORE = 0, /* nothing yet */
	EVO_SLCAN_FRAME,    /* a frame: *f is filled */
	EVO_SLCAN_EMPTY,    /* an empty line (e.g. the LF of CR LF): ignored */
	EVO_SLCAN_BAD	    /* a refused line: *bad says why */
} evo_slcan_result;

/* A line being received. Zero it (or call evo_slcan_rx_init) to start. */
typedef struct evo_slcan_rx {
	char line[EVO_SLCAN_LINE_MAX];
	uint8_t n;	  /* characters in line */
	uint8_t overlong; /* the line outgrew line: skipping to its end */
} evo_slcan_rx;

void evo_slcan_rx_init(evo_slcan_rx *rx);

/* Feed one received byte; a line ends at CR or LF. Any byte value is
 * accepted: nothing a sender writes can overflow rx or stop it. */
evo_slcan_result evo_slcan_rx_byte(evo_slcan_rx *rx, uint8_t c,
				   evo_can_frame *f, evo_wire_bad *bad);

/* Decode one line without its end: "tIIILDD..", hex digits in either
 * case. EVO_SLCAN_FRAME, EVO_SLCAN_EMPTY (n == 0) or EVO_SLCAN_BAD. */
evo_slcan_result evo_slcan_decode(const char *line, size_t n,
				  evo_can_frame *f, evo_wire_bad *bad);

/* Write f as an slcan line, upper-case hex, ending in CR, into buf (at
 * least EVO_SLCAN_LINE_MAX + 1 bytes; not NUL-terminated). Returns the
 * characters written. f->id must be below 0x800 and f->len at most 8. */
size_t evo_slcan_encode(const evo_can_frame *f, char *buf);

#endif
