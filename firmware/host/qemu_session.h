/* A firmware running under qemu-system-arm, driven over its serial line
 * as slcan frames (evo/wire.h): start it, send frames, read the
 * frames and log lines it sends back, stop it. Used by the firmware test
 * driver and by bench/bench_firmware.c.
 *
 * Every session has a deadline: past it QEMU is killed, so a test can
 * never hang; QEMU also dies with the process that started it. */
#ifndef EVO_FW_QEMU_SESSION_H
#define EVO_FW_QEMU_SESSION_H

#include <stddef.h>
#include <sys/types.h>

#include "trace_file.h"
#include "evo/wire.h"

typedef struct qemu_opts {
	const char *qemu;    /* qemu-system-arm */
	const char *machine; /* microbit, mps2-an385 */
	const char *kernel;  /* the firmware ELF */
	const char *plugin;  /* "insn_count.so,arg=..,..." or NULL */
	const char *stderr_path; /* QEMU's stderr goes here (NULL: dropped) */
	double deadline_s;   /* killed after this many seconds */
} qemu_opts;

typedef struct qemu_session {
	pid_t pid;
	int to_guest, from_guest; /* pipe ends, non-blocking */
	double deadline;	  /* monotonic seconds */
	char in[65536];		  /* received bytes not yet returned */
	size_t in_len;
	int eof;	    /* the guest's output has ended */
	int exited, status; /* status: exit status, or 128 + signal */
	char out[1 << 16];  /* bytes queued for the guest */
	size_t out_len;
} qemu_session;

/* What qs_next returns. */
enum {
	QS_TIMEOUT = 0, /* nothing within the time asked */
	QS_FRAME,	/* *f filled */
	QS_LOG,		/* a line starting with '#': line filled */
	QS_JUNK,	/* a line that is neither: line filled */
	QS_EXIT,	/* the guest stopped: q->status */
};

/* Seconds on the monotonic clock. */
double qs_now(void);

/* Start QEMU. 0, or -1 with a message in err. */
int qs_start(qemu_session *q, const qemu_opts *o, char *err, size_t cap);

/* Queue bytes or a frame for the guest; qs_flush or qs_next send them. */
void qs_queue(qemu_session *q, const char *data, size_t n);
void qs_queue_frame(qemu_session *q, const evo_can_frame *f);

/* Queue tick i of trace t: every sensor frame (full, which tick 0 needs),
 * or only those whose values differ from tick i - 1's, with their mask in
 * the tick frame (docs/wire.md). More than 32 sensor frames are always
 * sent in full. */
void qs_queue_trace_tick(qemu_session *q, const trace_file *t, size_t i,
			 int full);

/* Send everything queued (reading what the guest sends meanwhile, so
 * neither side blocks). 0, or -1 when the guest stopped or the deadline
 * passed. */
int qs_flush(qemu_session *q);

/* The next frame or line from the guest within timeout_s, sending what is
 * queued meanwhile. line (cap bytes) gets log and junk lines. */
int qs_next(qemu_session *q, double timeout_s, evo_can_frame *f, char *line,
	    size_t cap);

/* Wait up to timeout_s for the guest to stop by itself: its exit status,
 * or -1 (then it is killed). */
int qs_wait_exit(qemu_session *q, double timeout_s);

/* Ask QEMU to quit (SIGTERM: it exits cleanly, so plugins write their
 * results) and wait up to timeout_s; then kill it. Its exit status. */
int qs_terminate(qemu_session *q, double timeout_s);

/* Kill QEMU (if running) and reap it. */
void qs_stop(qemu_session *q);

#endif
