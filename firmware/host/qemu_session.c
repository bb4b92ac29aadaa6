/* A firmware under qemu-system-arm, driven over its serial line
 * (firmware/host/qemu_session.h). */
#define _GNU_SOURCE
#include "qemu_session.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

double qs_now(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

int qs_start(qemu_session *q, const qemu_opts *o, char *err, size_t cap)
{
	int in_pipe[2], out_pipe[2];
	memset(q, 0, sizeof *q);
	q->pid = -1;
	/* A write to a QEMU that died is an error to report, not a signal. */
	signal(SIGPIPE, SIG_IGN);
	if (pipe(in_pipe) != 0 || pipe(out_pipe) != 0) {
		snprintf(err, cap, "pipe: %s", strerror(errno));
		return -1;
	}
	const char *argv[24];
	int n = 0;
	argv[n++] = o->qemu;
	argv[n++] = "-M";
	argv[n++] = o->machine;
	argv[n++] = "-nographic";
	argv[n++] = "-monitor";
	argv[n++] = "none";
	argv[n++] = "-serial";
	argv[n++] = "stdio";
	argv[n++] = "-semihosting-config";
	argv[n++] = "enable=on,target=native";
	argv[n++] = "-kernel";
	argv[n++] = o->kernel;
	if (o->plugin) {
		argv[n++] = "-plugin";
		argv[n++] = o->plugin;
	}
	argv[n] = NULL;
	pid_t parent = getpid();
	pid_t pid = fork();
	if (pid < 0) {
		snprintf(err, cap, "fork: %s", strerror(errno));
		return -1;
	}
	if (pid == 0) {
		/* QEMU dies with the driver, whatever kills the driver. */
		prctl(PR_SET_PDEATHSIG, SIGKILL);
		if (getppid() != parent)
			_exit(127);
		/* QEMU runs at the driver's priority: the robot's clock is
		 * the host's wall clock (board_millis), so an emulator kept
		 * off the CPU only slows the ticks it answers, and at nice 10
		 * beside two busy programs a tick took over a second
		 * (docs/firmware.md). */
		dup2(in_pipe[0], 0);
		dup2(out_pipe[1], 1);
		int e = open(o->stderr_path ? o->stderr_path : "/dev/null",
			     O_WRONLY | O_CREAT | O_TRUNC, 0644);
		if (e >= 0)
			dup2(e, 2);
		for (int fd = 3; fd < 256; fd++)
			close(fd);
		execvp(o->qemu, (char *const *)argv);
		fprintf(stderr, "cannot run %s: %s\n", o->qemu,
			strerror(errno));
		_exit(127);
	}
	close(in_pipe[0]);
	close(out_pipe[1]);
	q->pid = pid;
	q->to_guest = in_pipe[1];
	q->from_guest = out_pipe[0];
	fcntl(q->to_guest, F_SETFL, O_NONBLOCK);
	fcntl(q->from_guest, F_SETFL, O_NONBLOCK);
	q->deadline = qs_now() + o->deadline_s;
	return 0;
}

void qs_queue(qemu_session *q, const char *data, size_t n)
{
	while (n) {
		if (q->out_len == sizeof q->out && qs_flush(q) != 0)
			return;
		size_t room = sizeof q->out - q->out_len;
		size_t k = n < room ? n : room;
		memcpy(q->out + q->out_len, data, k);
		q->out_len += k;
		data += k;
		n -= k;
	}
}

void qs_queue_frame(qemu_session *q, const evo_can_frame *f)
{
	char line[EVO_SLCAN_LINE_MAX + 1];
	qs_queue(q, line, evo_slcan_encode(f, line));
}

/* Reap QEMU if it has stopped. */
static void check_exit(qemu_session *q, int block)
{
	int st;
	if (q->exited || q->pid < 0)
		return;
	pid_t r = waitpid(q->pid, &st, block ? 0 : WNOHANG);
	if (r == q->pid) {
		q->exited = 1;
		q->status = WIFEXITED(st) ? WEXITSTATUS(st)
					  : 128 + WTERMSIG(st);
	}
}

/* One round of I/O: wait up to timeout_s for the guest's output or room to
 * write; read and write what can be. -1 when the guest's output ended. */
static int pump(qemu_session *q, double timeout_s)
{
	struct pollfd p[2] = {{q->from_guest, POLLIN, 0},
			      {q->to_guest, POLLOUT, 0}};
	int np = q->out_len ? 2 : 1;
	int ms = timeout_s <= 0 ? 0 : (int)(timeout_s * 1000) + 1;
	if (poll(p, (nfds_t)np, ms) < 0 && errno != EINTR)
		return -1;
	if (np == 2 && (p[1].revents & (POLLOUT | POLLERR | POLLHUP))) {
		ssize_t w = write(q->to_guest, q->out, q->out_len);
		if (w > 0) {
			memmove(q->out, q->out + w, q->out_len - (size_t)w);
			q->out_len -= (size_t)w;
		} else if (w < 0 && errno != EAGAIN && errno != EINTR) {
			q->out_len = 0; /* the guest is gone */
		}
	}
	if (p[0].revents & (POLLIN | POLLHUP | POLLERR)) {
		if (q->in_len == sizeof q->in)
			q->in_len = 0; /* a line longer than the buffer: junk */
		ssize_t r = read(q->from_guest, q->in + q->in_len,
				 sizeof q->in - q->in_len);
		if (r > 0)
			q->in_len += (size_t)r;
		else if (r == 0)
			return -1;
	}
	return 0;
}

int qs_flush(qemu_session *q)
{
	while (q->out_len) {
		if (qs_now() > q->deadline) {
			qs_stop(q);
			return -1;
		}
		if (pump(q, 0.05) != 0)
			return -1;
		check_exit(q, 0);
		if (q->exited)
			return -1;
	}
	return 0;
}

/* Take one whole line from q->in into line; 1 if there was one. */
static int take_line(qemu_session *q, char *line, size_t cap, size_t *n)
{
	size_t start = 0;
	while (start < q->in_len &&
	       (q->in[start] == '\r' || q->in[start] == '\n'))
		start++;
	size_t end = start;
	while (end < q->in_len && q->in[end] != '\r' && q->in[end] != '\n')
		end++;
	if (end == q->in_len) {
		memmove(q->in, q->in + start, q->in_len - start);
		q->in_len -= start;
		return 0;
	}
	*n = end - start;
	size_t k = *n < cap - 1 ? *n : cap - 1;
	memcpy(line, q->in + start, k);
	line[k] = 0;
	memmove(q->in, q->in + end, q->in_len - end);
	q->in_len -= end;
	return 1;
}

int qs_next(qemu_session *q, double timeout_s, evo_can_frame *f, char *line,
	    size_t cap)
{
	double until = qs_now() + timeout_s;
	char buf[512];
	for (;;) {
		size_t n;
		if (take_line(q, buf, sizeof buf, &n)) {
			evo_wire_bad bad;
			if (buf[0] == '#') {
				snprintf(line, cap, "%s", buf);
				return QS_LOG;
			}
			if (n < sizeof buf &&
			    evo_slcan_decode(buf, n, f, &bad) ==
				    EVO_SLCAN_FRAME)
				return QS_FRAME;
			snprintf(line, cap, "%s", buf);
			return QS_JUNK;
		}
		if (q->eof) {
			check_exit(q, 1);
			return QS_EXIT;
		}
		double now = qs_now();
		if (now > q->deadline) {
			qs_stop(q);
			return QS_EXIT;
		}
		if (now > until)
			return QS_TIMEOUT;
		double wait = until - now;
		if (wait > 0.05)
			wait = 0.05;
		if (pump(q, wait) != 0)
			q->eof = 1; /* output ended: QEMU is stopping */
		check_exit(q, 0);
	}
}

int qs_wait_exit(qemu_session *q, double timeout_s)
{
	double until = qs_now() + timeout_s;
	while (!q->exited && qs_now() < until && qs_now() < q->deadline) {
		if (q->eof || pump(q, 0.05) != 0) {
			q->eof = 1;
			check_exit(q, 1);
		} else {
			check_exit(q, 0);
		}
	}
	if (!q->exited) {
		qs_stop(q);
		return -1;
	}
	return q->status;
}

int qs_terminate(qemu_session *q, double timeout_s)
{
	if (q->pid > 0 && !q->exited)
		kill(q->pid, SIGTERM);
	return qs_wait_exit(q, timeout_s);
}

void qs_stop(qemu_session *q)
{
	if (q->pid > 0 && !q->exited) {
		kill(q->pid, SIGKILL);
		check_exit(q, 1);
	}
	if (q->to_guest > 0)
		close(q->to_guest);
	if (q->from_guest > 0)
		close(q->from_guest);
	q->to_guest = q->from_guest = -1;
}

void qs_queue_trace_tick(qemu_session *q, const trace_file *t, size_t i,
			 int full)
{
	evo_can_frame f;
	const int32_t *s = t->sensor + i * t->n_sensors;
	const int32_t *prev = s - t->n_sensors;
	unsigned frames = evo_wire_frames(t->n_sensors);
	uint32_t mask = 0;
	if (frames > 32)
		full = 1;
	for (unsigned k = 0; k < frames; k++) {
		unsigned n = 2 * k + 1 < t->n_sensors ? 2 : 1;
		if (!full &&
		    memcmp(s + 2 * k, prev + 2 * k, n * sizeof *s) == 0)
			continue;
		evo_wire_pack(EVO_WIRE_SENSOR, s, t->n_sensors, k, &f);
		qs_queue_frame(q, &f);
		mask |= 1u << k;
	}
	f.id = EVO_WIRE_TICK;
	f.len = full ? 4 : 8;
	evo_wire_put_u32(f.data, t->tick[i]);
	evo_wire_put_u32(f.data + 4, mask);
	qs_queue_frame(q, &f);
}
