/* evo — a mind image sent over CAN to a running robot (evo flash): the
 * frames of the transfer, the robot's receiver and the host's sender.
 *
 * The host begins a transfer, sends the image in numbered segments of 7
 * bytes, a window of them at a time, and ends it with the CRC-32 of the
 * whole image. The robot writes the segments into a slot its running mind
 * does not use, acknowledges them, asks for them again from the first one
 * missing when a frame was lost, and at the end checks the CRC, the image
 * (evo_mind_open: layout, names hash) and the state's size; only then does
 * its firmware switch to the new mind, between two ticks. Anything else
 * ends the transfer with a reason, and the running mind is untouched.
 *
 * Portable C11 and freestanding, like wire.h: the firmware receives with
 * this code, `evo flash` sends with it, and the tests and the fuzz target
 * drive both. docs/wire.md ("Sending a mind") is the reference for the
 * frames; this header is the API. */
#ifndef EVO_FLASH_H
#define EVO_FLASH_H

#include <stddef.h>
#include <stdint.h>

#include "evo/mind.h"
#include "evo/wire.h"

/* ---- the frames (docs/wire.md) ---------------------------------------- */

/* host -> robot, DLC 8: version (u8, EVO_FLASH_VERSION), window asked
 * (u8: bits 0-6 segments in flight at most, 1 .. EVO_FLASH_WINDOW_MAX; bit
 * 7 EVO_FLASH_FORCE), the image's length in 4-byte words (u16), the names
 * hash in the image's header (u32). Begins a transfer, abandoning one under
 * way. */
#define EVO_FLASH_BEGIN 0x1D0u
/* host -> robot, DLC 2 .. 8: segment number (u8, its low 8 bits), then
 * the segment: image bytes 7k .. 7k+6 for segment k (fewer for the last). */
#define EVO_FLASH_DATA 0x1D1u
/* host -> robot, DLC 8: CRC-32 (evo_crc32) of the whole image (u32), the
 * transfer's counter (u32; the robot takes only one above its own, unless
 * forced). */
#define EVO_FLASH_END 0x1D2u
/* robot -> host, DLC 8: kind (u8, EVO_FLASH_READY ..), reason (u8,
 * evo_flash_reason; for READY the window granted), next segment expected
 * (u16; for READY flags, EVO_FLASH_KEYED), detail (u32, per kind and
 * reason: see evo_flash_reason). */
#define EVO_FLASH_REPLY 0x1D3u
/* host -> robot, DLC 8, only to a robot with a key, before END: the
 * transfer's tag (evo_flash_tag 'I' over BEGIN, the image and END). */
#define EVO_FLASH_AUTH 0x1D4u
/* robot -> host, DLC 8, only from a robot with a key, right after its
 * READY and its DONE: the reply's tag (evo_flash_tag 'R' over BEGIN, the
 * reply, and END or 8 zero bytes before it). */
#define EVO_FLASH_TAG 0x1D5u

#define EVO_FLASH_VERSION 2u
#define EVO_FLASH_FORCE 0x80u /* BEGIN's window byte: take any counter */
#define EVO_FLASH_KEYED 1u    /* READY's flags: the robot has a key */
/* A robot's counter goes up to this; the erased flash's 0xFFFFFFFF is no
 * counter (a slot that never had one counts as 0). */
#define EVO_FLASH_COUNTER_MAX 0xFFFFFFFEu
#define EVO_FLASH_TAG_BYTES 8u /* HMAC-SHA-256 truncated, as SecOC does */
#define EVO_FLASH_KEY_MIN 16u  /* bytes of a key */
#define EVO_FLASH_KEY_MAX 64u
#define EVO_FLASH_SEGMENT 7u /* image bytes per DATA frame */
#define EVO_FLASH_WINDOW_MAX                                                   \
	64u /* below 128: the 8-bit segment numbers                            \
	       of a window are never ambiguous */

/* What a REPLY says. */
typedef enum evo_flash_kind {
	EVO_FLASH_READY = 0,   /* BEGIN taken; reason: the window granted;
				  detail: the bytes the slot holds */
	EVO_FLASH_ACK = 1,     /* every segment before `next` has arrived */
	EVO_FLASH_RESEND = 2,  /* a segment came out of sequence (reason
				  SEQUENCE) or malformed (FRAME): send
				  again from `next` */
	EVO_FLASH_DONE = 3,    /* the new mind runs; detail: the number of
				  the last tick the old mind answered */
	EVO_FLASH_REFUSED = 4, /* the transfer is over and nothing changed:
				  the running mind goes on */
} evo_flash_kind;

/* Why a transfer was refused, with what the reply's detail carries. One
 * list makes the codes and their messages. */
#define EVO_FLASH_REASON_LIST(X)                                               \
	X(EVO_FLASH_OK, "ok")                                                  \
	/* detail: the robot's version */                                      \
	X(EVO_FLASH_ERR_VERSION,                                               \
	  "the robot speaks another version of the transfer")                  \
	/* detail: the bytes the robot's slot holds */                         \
	X(EVO_FLASH_ERR_SIZE,                                                  \
	  "the image is larger than the robot's mind slot")                    \
	X(EVO_FLASH_ERR_NO_TRANSFER,                                           \
	  "no transfer is under way (none was begun, or it has ended)")        \
	X(EVO_FLASH_ERR_SEQUENCE,                                              \
	  "a segment came out of sequence (a frame was lost)")                 \
	X(EVO_FLASH_ERR_FRAME, "a frame of the transfer had the wrong length") \
	/* detail: the segments that had arrived */                            \
	X(EVO_FLASH_ERR_INCOMPLETE,                                            \
	  "the transfer ended before every segment had arrived")               \
	/* detail: the CRC-32 of what the robot received */                    \
	X(EVO_FLASH_ERR_CRC,                                                   \
	  "the image arrived corrupted: the transfer's CRC-32 does not "       \
	  "match")                                                             \
	/* detail: the robot's names hash (the BEGIN carried the image's) */   \
	X(EVO_FLASH_ERR_NAMES,                                                 \
	  "the image was built for another robot: other sensors, actuators "   \
	  "or variables")                                                      \
	/* detail: the core's evo_status (evo_status_str says it) */           \
	X(EVO_FLASH_ERR_IMAGE, "the robot refused the image")                  \
	/* detail: the bytes of RAM the new mind's state needs */              \
	X(EVO_FLASH_ERR_STATE,                                                 \
	  "the new mind's state needs more RAM than the robot has for it")     \
	/* detail: the slot offset that did not take the bytes */              \
	X(EVO_FLASH_ERR_WRITE, "the robot could not write its mind slot")      \
	/* detail: the robot's transfer timeout, ms */                         \
	X(EVO_FLASH_ERR_TIMEOUT,                                               \
	  "the transfer stopped: the robot heard nothing of it for its "       \
	  "transfer timeout")                                                  \
	/* detail: the robot's counter */                                      \
	X(EVO_FLASH_ERR_STALE,                                                 \
	  "the transfer's counter is not above the robot's: a transfer "       \
	  "replayed, or one older than the robot's mind")                      \
	X(EVO_FLASH_ERR_AUTH,                                                  \
	  "the transfer's tag is missing or wrong: it was not sent with the "  \
	  "robot's key")                                                       \
	/* the last two are the sender's own conclusions from a READY */       \
	X(EVO_FLASH_ERR_KEYED,                                                 \
	  "the robot takes only transfers sent with its key")                  \
	X(EVO_FLASH_ERR_UNKEYED,                                               \
	  "the robot has no key: it would take anyone's transfer, so a "       \
	  "transfer with a key is not sent to it")

typedef enum evo_flash_reason {
#define EVO_FLASH_REASON_ENUM(code, text) code,
	EVO_FLASH_REASON_LIST(EVO_FLASH_REASON_ENUM)
#undef EVO_FLASH_REASON_ENUM
	    EVO_FLASH_REASON_COUNT
} evo_flash_reason;

/* The message for a reason; never NULL. */
const char *evo_flash_reason_str(evo_flash_reason r);

/* The longest image a transfer carries: its length in words is a u16. */
#define EVO_FLASH_LENGTH_MAX (4u * 0xFFFFu)

/* Segments of an image of len bytes. */
static inline uint32_t evo_flash_segments(uint32_t len)
{
	return (len + EVO_FLASH_SEGMENT - 1u) / EVO_FLASH_SEGMENT;
}

/* A REPLY frame, as sent. */
void evo_flash_reply(evo_can_frame *f, evo_flash_kind kind, uint8_t reason,
		     uint32_t next, uint32_t detail);

/* The first EVO_FLASH_TAG_BYTES of HMAC-SHA-256 under key (key_len
 * bytes) of: the domain byte ('I' a transfer's image, 'R' a reply, 'C' a
 * CONFIG), a (8 bytes), body (n bytes, may be NULL when n is 0), b (8
 * bytes). Each kind binds what it must (docs/wire.md, "Keys"). */
void evo_flash_tag(const uint8_t *key, size_t key_len, uint8_t domain,
		   const uint8_t a[8], const uint8_t *body, uint32_t n,
		   const uint8_t b[8], uint8_t tag[EVO_FLASH_TAG_BYTES]);

/* ---- the robot's receiver ------------------------------------------------ */

/* Program one 4-byte word at offset (4-byte aligned, increasing from 0
 * within a transfer) of the target slot; the slot is read back through
 * its memory. 0, or -1 when the write failed. A board whose slot is flash
 * erases a page when a transfer first writes into it. */
typedef int (*evo_flash_write_fn)(void *ctx, uint32_t offset,
				  const uint8_t word[4]);

typedef struct evo_flash_rx_def {
	uint32_t names_hash; /* this robot's (evo_names_hash) */
	uint32_t state_max;  /* bytes of RAM for a mind state */
	uint32_t timeout_ms; /* a transfer silent this long is abandoned */
	uint8_t window;	     /* most segments in flight this robot grants */
	evo_flash_write_fn write;
	void *ctx;
	/* The robot's key (EVO_FLASH_KEY_MIN .. _MAX bytes, kept by the
	 * caller), or NULL: with one, a transfer switches only with its
	 * tag, and READY and DONE are followed by theirs. */
	const uint8_t *key;
	uint32_t key_len;
} evo_flash_rx_def;

typedef struct evo_flash_rx {
	evo_flash_rx_def def;
	const uint8_t *slot; /* where the next transfer goes (4-aligned) */
	uint32_t slot_size;
	/* the transfer under way */
	uint8_t active;
	uint8_t window;	  /* granted */
	uint8_t quiet;	  /* refused: said once, the rest of it ignored */
	uint8_t gap_said; /* a RESEND was sent for the current gap */
	uint8_t dup_said; /* an ACK was sent for the current duplicates */
	uint8_t n_word;	  /* bytes in word */
	uint8_t word[4];  /* image bytes not yet written */
	uint32_t length;  /* image bytes */
	uint32_t next;	  /* segment expected */
	uint32_t acked;	  /* next, as the last ACK or RESEND said it */
	uint32_t written; /* bytes written to the slot */
	uint32_t crc;	  /* evo_crc32 of the written bytes, read back */
	uint32_t last_ms; /* when the last frame of it came */
	uint8_t force;	  /* BEGIN said EVO_FLASH_FORCE */
	uint8_t has_tag;  /* an AUTH came since BEGIN */
	uint8_t begin[8]; /* BEGIN's bytes, which the tags bind */
	uint8_t end[8];	  /* END's, once it came */
	uint8_t tag[EVO_FLASH_TAG_BYTES]; /* AUTH's */
	/* The counter of the running mind's transfer (0: none), which a
	 * new one must exceed; the caller sets it from the running slot
	 * (evo_flash_rx_counter_at). */
	uint32_t counter;
	/* the transfer that switched last, so a repeated END (its DONE
	 * lost) is answered DONE again */
	uint8_t done;
	uint32_t done_length, done_crc, done_tick;
	/* the verified mind, after EVO_FLASH_RX_SWITCH */
	evo_mind mind;
	/* Frames of the last EVO_FLASH_RX_REPLY: 1, or 2 when the reply's
	 * tag follows it (reply[1]). */
	uint8_t replies;
} evo_flash_rx;

/* Room for what one call answers: a reply and its tag. */
#define EVO_FLASH_RX_REPLIES 2

typedef enum evo_flash_rx_result {
	EVO_FLASH_RX_NONE = 0, /* nothing to send */
	EVO_FLASH_RX_REPLY,    /* send *reply */
	EVO_FLASH_RX_SWITCH,   /* rx->mind is the verified new mind: switch
				  to it, then call evo_flash_rx_switched */
} evo_flash_rx_result;

void evo_flash_rx_init(evo_flash_rx *rx, const evo_flash_rx_def *def);

/* Where the next transfer writes: a slot the running mind does not use. */
void evo_flash_rx_target(evo_flash_rx *rx, const uint8_t *slot, uint32_t size);

/* The counter a transfer left in a slot with its image of image_len bytes
 * (the word after the image; 0 when there is none: erased flash, or a
 * slot whose image was built in). The slot holds size bytes. */
uint32_t evo_flash_rx_counter_at(const uint8_t *slot, uint32_t size,
				 uint32_t image_len);

/* A frame with id EVO_FLASH_BEGIN, DATA, AUTH or END, received at now_ms.
 * reply has room for EVO_FLASH_RX_REPLIES frames; rx->replies says how
 * many to send. On EVO_FLASH_RX_SWITCH the transfer's counter has been
 * written after the image (the slot's next word). */
evo_flash_rx_result evo_flash_rx_frame(evo_flash_rx *rx, const evo_can_frame *f,
				       uint32_t now_ms, evo_can_frame *reply);

/* Time passing: a transfer silent for the timeout is abandoned (REPLY:
 * REFUSED, TIMEOUT). */
evo_flash_rx_result evo_flash_rx_poll(evo_flash_rx *rx, uint32_t now_ms,
				      evo_can_frame *reply);

/* After EVO_FLASH_RX_SWITCH, once the firmware runs rx->mind: the DONE
 * reply (and its tag: rx->replies frames), naming the last tick the old
 * mind answered. */
void evo_flash_rx_switched(evo_flash_rx *rx, uint32_t last_tick,
			   evo_can_frame *reply);

/* A CONFIG frame (evo/wire.h's EVO_WIRE_CONFIG) checked as this robot
 * takes it: 1 with *timeout_ms when it is to be taken, else 0. Without a
 * key: DLC 2. With one: DLC 8, the timeout then the first 6 bytes of
 * evo_flash_tag 'C' over (timeout, the robot's counter). The caller bounds
 * the value. */
int evo_flash_config_check(const evo_flash_rx *rx, const evo_can_frame *f,
			   uint32_t *timeout_ms);
/* The keyed CONFIG a host sends to a robot whose counter is counter. */
void evo_flash_config_make(const uint8_t *key, size_t key_len,
			   uint32_t counter, uint16_t timeout_ms,
			   evo_can_frame *f);

/* ---- the host's sender -----------------------------------------------------
 */

typedef enum evo_flash_tx_stage {
	EVO_FLASH_TX_BEGIN = 0,
	EVO_FLASH_TX_DATA,
	EVO_FLASH_TX_END,
	EVO_FLASH_TX_FINISHED /* DONE or REFUSED came: see kind */
} evo_flash_tx_stage;

typedef struct evo_flash_tx {
	const uint8_t *image;
	uint32_t length, total; /* bytes, segments */
	uint8_t window;		/* asked, then granted */
	evo_flash_tx_stage stage;
	uint8_t waiting;   /* BEGIN or END sent, its answer awaited */
	uint8_t waiting_auth; /* AUTH sent, END next */
	uint32_t acked;	   /* segments the robot said it has */
	uint32_t next;	   /* the next segment to send */
	uint32_t sent;	   /* segments sent at least once since READY */
	uint32_t crc;	   /* of the whole image */
	uint32_t progress; /* counts replies that moved the transfer on */
	/* What was sent, which every reply is checked against: BEGINs
	 * sent and READYs taken (one READY per BEGIN), END's bytes. */
	uint32_t begins, readies;
	uint8_t begin[8], end[8];
	/* the counter: set (evo_flash_tx_counter), or the robot's + 1 */
	uint8_t counter_set, force;
	uint32_t counter;
	uint32_t robot_counter; /* from READY */
	const uint8_t *key;	/* evo_flash_tx_key, or NULL */
	uint32_t key_len;
	/* a READY or DONE whose tag is awaited (keyed) */
	uint8_t pending;
	uint8_t pending_reply[8];
	/* once FINISHED: the last reply */
	evo_flash_kind kind;
	evo_flash_reason reason;
	uint32_t detail;
	/* counters: replies dropped because they did not answer what was
	 * sent (forged, stale, out of turn), tags that did not verify */
	uint32_t frames, resent_segments, resends_asked;
	uint32_t replies_dropped, tags_bad;
} evo_flash_tx;

/* Send image (len bytes, a multiple of 4 up to EVO_FLASH_LENGTH_MAX, kept
 * by the caller; its header's names hash goes in BEGIN) with a window of
 * segments in flight (1 .. EVO_FLASH_WINDOW_MAX; clamped). */
void evo_flash_tx_init(evo_flash_tx *t, const uint8_t *image, uint32_t len,
		       unsigned window);

/* Send with key (key_len bytes, kept by the caller): the transfer carries
 * its tag, and only a READY and a DONE with theirs are taken. */
void evo_flash_tx_key(evo_flash_tx *t, const uint8_t *key, size_t key_len);

/* Send counter (0: the robot's + 1, as without this call); force: the
 * robot takes it even when it is not above its own (docs/wire.md,
 * "Freshness"). */
void evo_flash_tx_counter(evo_flash_tx *t, uint32_t counter, int force);

/* The next frame to send now: 1 with *f, or 0 when the sender waits for a
 * reply (or is finished). */
int evo_flash_tx_next(evo_flash_tx *t, evo_can_frame *f);

/* A frame from the bus; anything but a well-formed REPLY (or TAG) that
 * answers what was sent is ignored, and counted (replies_dropped). */
void evo_flash_tx_reply(evo_flash_tx *t, const evo_can_frame *f);

/* No reply within the caller's timeout: send again what is not yet
 * acknowledged (BEGIN, the segments from the last ACK, or END). */
void evo_flash_tx_timeout(evo_flash_tx *t);

#endif
