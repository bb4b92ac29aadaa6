/* fw_run: a firmware under qemu-system-arm on a CAN bus of evo's, for a
 * user to try it with evo's tools (`make firmware-run`, docs/firmware.md).
 *
 * The firmware's UART carries the bus as slcan lines (qemu_session.h);
 * fw_run passes every frame between it and each `--can URL` (a
 * `slcan-pty:?link=PATH` each, by make firmware-run: evo is the adapter
 * there, so `evo flash --can slcan:PATH` and `evo serve --can
 * slcan:PATH` open it as they would a USB adapter), and every frame of
 * one port to the others, as a bus would. The firmware's own lines (`#
 * ...`) are printed.
 *
 * A body (`evo serve TASK --robot --can ...`) waits for a mind to start
 * an episode; the firmware does not (a robot's body would start with it),
 * so with --episode-seed N fw_run starts one: on each BODY frame of a
 * port it sends that port LAYOUT_SEED, SEED and RESET for the port's next
 * episode, with seed N. From then on the body ticks the firmware and the firmware's
 * mind drives the body.
 *
 * usage: fw_run --qemu QEMU --machine M --kernel ELF --can URL [--can URL]
 *               [--episode-seed N]
 * Runs until SIGINT or SIGTERM (exit 0) or until the firmware stops (its
 * exit status, as `# evo firmware: ...` said why). */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "qemu_session.h"
#include "remote/can.h"
#include "remote/can_robot.h"

#define MAX_PORTS 4

static volatile sig_atomic_t stop;

static void on_signal(int sig)
{
	(void)sig;
	stop = 1;
}

typedef struct port {
	const char *url;
	evo_can *can;
	uint32_t episodes; /* started for the bodies on it */
} port;

static int usage(void)
{
	fprintf(stderr, "usage: fw_run --qemu QEMU --machine M --kernel ELF "
			"--can URL [--can URL ...] [--episode-seed N]\n");
	return 2;
}

/* A frame to every port but `from` (-1: from the firmware). */
static void to_ports(port *p, int n, int from, const evo_can_frame *f)
{
	for (int k = 0; k < n; k++) {
		evo_err err = {{0}};
		if (k != from && evo_can_send(p[k].can, f, &err))
			fprintf(stderr, "fw_run: %s\n", err.msg);
	}
}

/* What the ports received: to the firmware and the other ports; a BODY
 * (a body starting, or answering a HELLO) starts an episode for it when
 * seeded. */
static void from_ports(qemu_session *q, port *p, int n, int seeded,
		       uint64_t seed)
{
	for (int k = 0; k < n; k++) {
		evo_can_frame f;
		evo_err err = {{0}};
		int got;
		while ((got = evo_can_recv(p[k].can, 0, &f, &err)) == 1) {
			qs_queue_frame(q, &f);
			to_ports(p, n, k, &f);
			if (f.id == EVO_WIRE_BODY && seeded) {
				evo_can_frame r[3];
				uint32_t e = ++p[k].episodes;
				evo_can_reset_encode(e, seed, seed, r);
				for (int i = 0; i < 3; i++)
					evo_can_send(p[k].can, &r[i], &err);
				printf("fw_run: %s: a body; episode %u started "
				       "with seed %llu\n",
				       p[k].url, (unsigned)e,
				       (unsigned long long)seed);
				fflush(stdout);
			}
		}
		if (got < 0)
			fprintf(stderr, "fw_run: %s\n", err.msg);
	}
}

int main(int argc, char **argv)
{
	qemu_opts o = {.deadline_s = 1e9};
	port p[MAX_PORTS];
	int n = 0, seeded = 0;
	uint64_t seed = 0;
	for (int i = 1; i < argc; i++) {
		const char *v = i + 1 < argc ? argv[i + 1] : NULL;
		if (!v)
			return usage();
		if (strcmp(argv[i], "--qemu") == 0)
			o.qemu = v;
		else if (strcmp(argv[i], "--machine") == 0)
			o.machine = v;
		else if (strcmp(argv[i], "--kernel") == 0)
			o.kernel = v;
		else if (strcmp(argv[i], "--can") == 0 && n < MAX_PORTS)
			p[n++] = (port){.url = v};
		else if (strcmp(argv[i], "--episode-seed") == 0) {
			seed = strtoull(v, NULL, 10);
			seeded = 1;
		} else
			return usage();
		i++;
	}
	if (!o.qemu || !o.machine || !o.kernel || n == 0)
		return usage();
	for (int k = 0; k < n; k++) {
		evo_err err = {{0}};
		p[k].can = evo_can_open(p[k].url, &err);
		if (!p[k].can) {
			fprintf(stderr, "fw_run: %s\n", err.msg);
			return 1;
		}
		const char *pty = evo_can_pty_name(p[k].can);
		printf("fw_run: the firmware's bus on %s%s%s\n", p[k].url,
		       pty ? ", device " : "", pty ? pty : "");
	}
	qemu_session q;
	char err[512];
	if (qs_start(&q, &o, err, sizeof err)) {
		fprintf(stderr, "fw_run: %s\n", err);
		return 1;
	}
	printf("fw_run: %s runs %s under %s (Ctrl-C stops it)\n", o.machine,
	       o.kernel, o.qemu);
	fflush(stdout);
	struct sigaction sa;
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_signal;
	sigaction(SIGINT, &sa, NULL);
	sigaction(SIGTERM, &sa, NULL);
	int rc = 0;
	while (!stop) {
		from_ports(&q, p, n, seeded, seed);
		evo_can_frame f;
		char line[512];
		int r = qs_next(&q, 0.002, &f, line, sizeof line);
		if (r == QS_FRAME) {
			to_ports(p, n, -1, &f);
		} else if (r == QS_LOG || r == QS_JUNK) {
			printf("%s\n", line);
			fflush(stdout);
		} else if (r == QS_EXIT) {
			printf("fw_run: the firmware stopped, exit status %d\n",
			       q.status);
			rc = q.status ? q.status : 1;
			break;
		}
	}
	if (!q.exited)
		qs_terminate(&q, 2.0);
	for (int k = 0; k < n; k++)
		evo_can_close(p[k].can);
	return rc;
}
