/* evo — CAN on the host (docs/can.md): classic CAN frames to and from a
 * robot's nodes, over whichever way reaches them, behind one interface
 * chosen by a URL:
 *
 *   socketcan:IFACE          raw frames through Linux's AF_CAN (can0,
 *                            vcan0)
 *   slcan:DEVICE[?bitrate=N] a serial device that speaks slcan (Lawicel),
 *                            as USB adapters do: closed, set to the bit
 *                            rate (default 500000), opened; its replies
 *                            checked
 *   slcan-pty:[?link=PATH]   a pseudo-terminal that speaks slcan, for a
 *                            peer on this machine (evo_can_pty_name says
 *                            which device to give it; PATH, a symbolic
 *                            link to it, removed on close)
 *   cannelloni:HOST:PORT[?local=LPORT]
 *                            CAN over UDP in cannelloni's version-2
 *                            datagrams, to a cannelloni (or evo) peer
 *   candump:FILE             a candump log (`candump -l`), read as a
 *                            source of frames in its order, at the pace
 *                            of its time stamps (as canplayer plays
 *                            one); sending to it appends to FILE.sent
 *
 * The frames are evo's (evo/wire.h): 11-bit ids, up to 8 bytes. Anything
 * else a bus carries (extended ids, remote frames, CAN FD) and any
 * malformed input is dropped and counted by reason, never taken. */
#ifndef EVO_CAN_H
#define EVO_CAN_H

#include <stddef.h>
#include <stdint.h>

#include "base/err.h"
#include "evo/wire.h"

typedef enum evo_can_bad {
	EVO_CAN_BAD_SYNTAX = 0, /* not a line or datagram of the format */
	EVO_CAN_BAD_LENGTH,	/* a length past the data or past 8 */
	EVO_CAN_BAD_OVERLONG,	/* a line longer than the format allows */
	EVO_CAN_BAD_NOT_OURS,	/* extended id, remote frame, CAN FD, error
				   frame: valid, but not evo's */
	EVO_CAN_BAD_VERSION,	/* a cannelloni version or op code evo does
				   not speak */
	EVO_CAN_BAD_REPLY,	/* an slcan adapter's error reply (BEL) */
	EVO_CAN_BAD_SOURCE,	/* a cannelloni datagram not from the peer
				   the URL names (its address and port) */
	EVO_CAN_BAD_COUNT
} evo_can_bad;

/* "syntax", "length", ... */
const char *evo_can_bad_name(evo_can_bad b);

/* ---- formats (pure functions: the fuzz targets' entry points) --------- */

/* cannelloni version 2: a 5-byte header (version 2, op code 0 DATA, a
 * sequence number, a big-endian count), then per frame a big-endian
 * 32-bit can_id, a length byte and the data. */
#define EVO_CANNELLONI_VERSION 2
#define EVO_CANNELLONI_MAX 1400 /* bytes in a datagram evo sends */

/* Decode a datagram: the frames that are evo's go to out (at most max),
 * *n of them. The others are counted in bad[] (EVO_CAN_BAD_COUNT
 * counters, added to). Returns 0, or -1 when the datagram as a whole is
 * refused (its header, or frames cut short), counted in bad[] too. */
int evo_cannelloni_decode(const uint8_t *d, size_t len, evo_can_frame *out,
			  int max, int *n, unsigned long *bad);

/* Encode frames f[0 .. n-1] with sequence number seq: the length, or 0
 * when they do not fit in cap bytes. */
size_t evo_cannelloni_encode(const evo_can_frame *f, int n, uint8_t seq,
			     uint8_t *out, size_t cap);

/* candump's log format: "(SECONDS.MICROS) IFACE ID#DATA", IFACE of
 * letters, digits, '_', '-' and '.', ID three hex digits (or eight for an
 * extended id, not evo's), DATA two hex digits a byte; "ID#R" is a remote
 * frame, "ID##F..." a CAN FD one (not evo's). A direction after a space,
 * " R" (received) or " T" (sent), as python-can writes it, is taken. */
#define EVO_CANDUMP_LINE_MAX 200

/* Parse one line (without its end). 1 with *f and *t filled, 0 for a
 * line not evo's or refused (*why set), and never more than len bytes
 * read. iface (EVO_CANDUMP_IFACE_MAX bytes) receives the interface. */
#define EVO_CANDUMP_IFACE_MAX 32
int evo_candump_parse(const char *line, size_t len, double *t, char *iface,
		      evo_can_frame *f, evo_can_bad *why);

/* Format f as a log line ending in '\n' into out (EVO_CANDUMP_LINE_MAX
 * bytes): its length. */
size_t evo_candump_format(const evo_can_frame *f, double t, const char *iface,
			  char *out);

/* slcan as the host reads it: lines of a serial stream, of which 't'
 * lines are evo's frames (core's evo_slcan_decode), 'T', 'r', 'R', 'd',
 * 'D', 'b', 'B' lines frames not evo's, a lone BEL an adapter's error
 * reply, 'z'/'Z' an adapter's acknowledgement of a frame sent. As the
 * adapter a peer drives (as_adapter), the commands C, O, S.., V, N and
 * the like are answered: CR, or a version or serial number. */
#define EVO_SLCAN_HOST_LINE 64
typedef struct evo_slcan_reader {
	int as_adapter;
	char line[EVO_SLCAN_HOST_LINE];
	size_t n;
	int overlong;
} evo_slcan_reader;

/* Feed n bytes: frames to out (at most max, *got of them; more are
 * counted as overlong input), drops added to bad[], and what evo must
 * answer (as the adapter) appended to reply (cap bytes, *reply_len in
 * it; an answer that does not fit is dropped). */
void evo_slcan_read(evo_slcan_reader *r, const char *b, size_t n,
		    evo_can_frame *out, int max, int *got, unsigned long *bad,
		    char *reply, size_t cap, size_t *reply_len);

/* ---- transports --------------------------------------------------------- */

typedef struct evo_can evo_can;

/* 0 when url names a transport above (its scheme), else -1 with err
 * set, as evo_can_open would say it; nothing is opened. */
int evo_can_url_check(const char *url, evo_err *err);

/* Open url (above). NULL with err set, saying what was wrong with the
 * URL or why the device could not be opened. */
evo_can *evo_can_open(const char *url, evo_err *err);
void evo_can_close(evo_can *c);

int evo_can_send(evo_can *c, const evo_can_frame *f, evo_err *err);

/* The next frame, waiting at most timeout_ms. 1 with *f filled, 0 when
 * none came, -1 with err set: an error, or the end of a candump source
 * (evo_can_ended then says so). */
int evo_can_recv(evo_can *c, int timeout_ms, evo_can_frame *f, evo_err *err);

/* 1 once a candump source has no more frames: evo_can_recv then
 * returns -1, saying that the log ended. */
int evo_can_ended(const evo_can *c);

/* Input dropped so far, by reason (EVO_CAN_BAD_COUNT counters). */
const unsigned long *evo_can_dropped(const evo_can *c);

/* slcan-pty: the device a peer opens (/dev/pts/N), and the link to it
 * (link=); NULL otherwise. */
const char *evo_can_pty_name(const evo_can *c);
const char *evo_can_pty_link(const evo_can *c);

/* Frames sent to a serial line (slcan, slcan-pty) that did not take them:
 * a peer that does not read, or none at all. They are dropped, as a bus
 * loses frames, and counted here; a send waits at most 2 ms for a line,
 * and not at all while it stays full. */
unsigned long evo_can_unsent(const evo_can *c);

#endif
