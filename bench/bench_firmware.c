/* make bench: the cost of one tick of the Collect hierarchy on a Cortex-M3,
 * as instructions counted in QEMU, beside the host's nanoseconds per tick
 * for the same ticks in the same run.
 *
 * The M3 figure: the firmware (BUILD/firmware/evo-m3.elf) runs under
 * qemu-system-arm -M mps2-an385 with the counting plugin
 * (BUILD/firmware/insn_count.so, firmware/qemu/insn_count.c), which counts
 * the instructions executed in the MIND runtime's code (its archive and
 * the libgcc helpers, __evo_runtime_start .. __evo_runtime_end in the
 * firmware's map, firmware/sections.ld) from the first call of
 * evo_mind_step on, and the calls of evo_mind_step. Apart, in the same
 * run, the instructions executed in the CAN frames and slcan lines
 * (core/src/wire.c, __evo_wire_start .. __evo_wire_end) that carry the
 * ticks' values: on the QEMU boards they cost more than the mind, and the
 * figure above counted them in before the runtime got a range of its own.
 * The rest of the firmware (main loop, UART, waiting) is in neither. The
 * trace's sensor values go in as slcan frames; every actuator value that
 * comes back must equal the trace's.
 * The host figure: evo_mind_step over the same sensor values, best of 5.
 *
 * Then the time `evo flash` takes to send the Collect image over slcan at
 * 115,200 baud: the transfer (core's evo/flash.h sender, window 16) runs
 * for real against the M3 firmware under QEMU, its frames and replies
 * counted as slcan lines; the time on a 115,200-baud line (8N1, 11,520
 * bytes a second each way) follows from the bytes sent to the robot, which
 * set the pace, beside the QEMU transfer's own wall time.
 *
 * usage: bench_firmware [--ticks N]  (from the top of the repo; BUILD from
 *        $EVO_BUILD, default build; qemu-system-arm and arm-none-eabi-nm
 *        from $QEMU_ARM and $ARM_NM or the PATH) */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_proc.h"
#include "bench_args.h"
#include "evo/flash.h"
#include "host/qemu_session.h"
#include "host/trace_file.h"
#include "mind/mindfolder.h"

static const char *build = "build";
static trace_file trace;

/* The address of a symbol of elf, or 0. */
static unsigned long symbol(const char *nm, const char *elf, const char *name)
{
	char cmd[1024], line[256];
	unsigned long addr = 0;
	snprintf(cmd, sizeof cmd, "%s %s", nm, elf);
	FILE *p = popen(cmd, "r");
	while (p && fgets(line, sizeof line, p)) {
		unsigned long a;
		char type, sym[200];
		if (sscanf(line, "%lx %c %199s", &a, &type, sym) == 3 &&
		    strcmp(sym, name) == 0)
			addr = a & ~1ul; /* no Thumb bit: QEMU's pc is even */
	}
	if (p)
		pclose(p);
	return addr;
}

/* Host: ns per tick of evo_mind_step over the trace's first n ticks. */
static double host_ns_per_tick(const char *mind_dir, size_t n, int *same)
{
	evo_err err;
	evo_mindfolder *l = evo_mindfolder_load(mind_dir, NULL, &err);
	if (!l) {
		fprintf(stderr, "%s\n", err.msg);
		return -1;
	}
	size_t size = evo_state_size(&l->mind);
	void *mem = aligned_alloc(8, (size + 7) & ~(size_t)7);
	evo_state *s;
	evo_q16 act[64];
	double best = 1e30;
	*same = 1;
	for (int rep = 0; rep < 5; rep++) {
		if (evo_state_init(&l->mind, mem, size, &s) != EVO_OK) {
			free(mem);
			evo_mindfolder_free(l);
			return -1;
		}
		double t0 = bench_now();
		for (size_t i = 0; i < n; i++) {
			evo_mind_step(&l->mind, s,
				      trace.sensor + i * trace.n_sensors, act);
			if (rep == 0 &&
			    memcmp(act, trace.actuator + i * trace.n_actuators,
				   trace.n_actuators * sizeof *act) != 0)
				*same = 0;
		}
		double dt = bench_now() - t0;
		if (dt < best)
			best = dt;
	}
	free(mem);
	evo_mindfolder_free(l);
	return best / (double)n * 1e9;
}

/* M3: instructions per tick in the runtime, or -1; *wire_out those in
 * the CAN frames and slcan lines. */
static double m3_insns_per_tick(size_t n, double *wire_out,
				unsigned long *marks_out)
{
	char elf[512], plugin[2048], out[512], err[256];
	const char *nm =
	    getenv("ARM_NM") ? getenv("ARM_NM") : "arm-none-eabi-nm";
	const char *qemu =
	    getenv("QEMU_ARM") ? getenv("QEMU_ARM") : "qemu-system-arm";
	snprintf(elf, sizeof elf, "%s/firmware/evo-m3.elf", build);
	snprintf(out, sizeof out, "%s/firmware/bench-insns.txt", build);
	unsigned long lo = symbol(nm, elf, "__evo_runtime_start"),
		      hi = symbol(nm, elf, "__evo_runtime_end"),
		      wire_lo = symbol(nm, elf, "__evo_wire_start"),
		      wire_hi = symbol(nm, elf, "__evo_wire_end"),
		      mark = symbol(nm, elf, "evo_mind_step");
	if (!lo || !hi || !wire_lo || !wire_hi || !mark) {
		fprintf(stderr,
			"bench_firmware: %s lacks __evo_runtime_start, "
			"__evo_runtime_end, __evo_wire_start, __evo_wire_end "
			"or evo_mind_step\n",
			elf);
		return -1;
	}
	snprintf(plugin, sizeof plugin,
		 "%s/firmware/insn_count.so,lo=0x%lx,hi=0x%lx,lo=0x%lx,"
		 "hi=0x%lx,mark=0x%lx,out=%s",
		 build, lo, hi, wire_lo, wire_hi, mark, out);
	remove(out);
	qemu_opts o = {qemu, "mps2-an385", elf, plugin, NULL, 120.0};
	qemu_session q;
	if (qs_start(&q, &o, err, sizeof err) != 0) {
		fprintf(stderr, "bench_firmware: %s\n", err);
		return -1;
	}
	evo_can_frame f;
	char line[512];
	size_t sent = 0, done = 0;
	int differ = 0, k;
	/* A link timeout a busy host cannot trip: the 100 ms default would
	 * set the actuators neutral whenever this machine is late, and the
	 * values would no longer be the trace's. */
	evo_can_frame patient = {EVO_WIRE_CONFIG, 2, {0}};
	evo_wire_put_u16(patient.data, 10000);
	qs_queue_frame(&q, &patient);
	while (done < n) {
		for (; sent < n && sent - done < 8; sent++)
			qs_queue_trace_tick(&q, &trace, sent, sent == 0);
		k = qs_next(&q, 10.0, &f, line, sizeof line);
		if (k == QS_LOG || (k == QS_FRAME && f.id == EVO_WIRE_HELLO))
			continue;
		if (k != QS_FRAME) {
			fprintf(stderr,
				"bench_firmware: the firmware stopped "
				"answering at tick %zu\n",
				done);
			qs_stop(&q);
			return -1;
		}
		if (f.id == EVO_WIRE_TICKED) {
			if (f.data[4] != 0)
				differ = 1;
			done++;
			continue;
		}
		evo_q16 v[64];
		const int32_t *want = trace.actuator + done * trace.n_actuators;
		int a = evo_wire_unpack(EVO_WIRE_ACTUATOR, &f, v,
					trace.n_actuators);
		if (a < 0)
			differ = 1;
		else
			for (unsigned j = 2 * (unsigned)a;
			     j < trace.n_actuators && j < 2 * (unsigned)a + 2;
			     j++)
				differ |= v[j] != want[j];
	}
	qs_terminate(&q, 10.0);
	qs_stop(&q);
	if (differ) {
		fprintf(stderr, "bench_firmware: the M3's actuator values "
				"differ from the trace's\n");
		return -1;
	}
	FILE *in = fopen(out, "r");
	unsigned long long total, marks, range, wire;
	int ok = in && fscanf(in, "insns %llu marks %llu range %llu range %llu",
			      &total, &marks, &range, &wire) == 4;
	if (in)
		fclose(in);
	if (!ok || marks == 0) {
		fprintf(stderr,
			"bench_firmware: no count from the plugin (%s)\n", out);
		return -1;
	}
	*marks_out = (unsigned long)marks;
	*wire_out = (double)wire / (double)marks;
	return (double)range / (double)marks;
}

/* Bytes of the slcan line of f: 't', 3 id digits, the DLC, 2 digits a
 * byte, CR. */
static size_t slcan_bytes(const evo_can_frame *f)
{
	return 6u + 2u * f->len;
}

/* The image of BUILD/firmware/mind/mind.bin sent to the M3 firmware. 0 and
 * the figures printed, or -1. */
static int flash_over_slcan(void)
{
	char path[512], err[512];
	snprintf(path, sizeof path, "%s/firmware/mind/mind.bin", build);
	FILE *fp = fopen(path, "rb");
	static _Alignas(8) uint8_t image[EVO_FLASH_LENGTH_MAX];
	size_t len = fp ? fread(image, 1, sizeof image, fp) : 0;
	if (fp)
		fclose(fp);
	if (len < 20) {
		fprintf(stderr, "bench_firmware: cannot read %s\n", path);
		return -1;
	}
	const char *qemu =
	    getenv("QEMU_ARM") ? getenv("QEMU_ARM") : "qemu-system-arm";
	char elf[512];
	snprintf(elf, sizeof elf, "%s/firmware/evo-m3.elf", build);
	qemu_opts o = {qemu, "mps2-an385", elf, NULL, NULL, 60.0};
	qemu_session q;
	if (qs_start(&q, &o, err, sizeof err) != 0) {
		fprintf(stderr, "bench_firmware: %s\n", err);
		return -1;
	}
	evo_can_frame f;
	char line[512];
	int k;
	while ((k = qs_next(&q, 10.0, &f, line, sizeof line)) == QS_LOG)
		;
	if (k != QS_FRAME || f.id != EVO_WIRE_HELLO) {
		fprintf(stderr, "bench_firmware: no HELLO from the M3\n");
		qs_stop(&q);
		return -1;
	}
	evo_flash_tx t;
	evo_flash_tx_init(&t, image, (uint32_t)len, 16);
	size_t out_bytes = 0, in_bytes = 0, replies = 0;
	double t0 = bench_now(), try_start = t0;
	uint32_t progress = t.progress;
	while (t.stage != EVO_FLASH_TX_FINISHED && bench_now() - t0 < 30.0) {
		while (evo_flash_tx_next(&t, &f)) {
			out_bytes += slcan_bytes(&f);
			qs_queue_frame(&q, &f);
		}
		k = qs_next(&q, 0.05, &f, line, sizeof line);
		if (k == QS_FRAME && f.id == EVO_FLASH_REPLY) {
			in_bytes += slcan_bytes(&f);
			replies++;
			evo_flash_tx_reply(&t, &f);
		} else if (k == QS_EXIT) {
			break;
		}
		if (t.progress != progress) {
			progress = t.progress;
			try_start = bench_now();
		} else if (bench_now() - try_start > 1.0) {
			evo_flash_tx_timeout(&t);
			try_start = bench_now();
		}
	}
	double wall = bench_now() - t0;
	qs_stop(&q);
	if (t.stage != EVO_FLASH_TX_FINISHED || t.kind != EVO_FLASH_DONE) {
		fprintf(stderr,
			"bench_firmware: the transfer did not finish\n");
		return -1;
	}
	const double line_bytes_per_s = 115200.0 / 10.0;
	printf("  evo flash:      image %zu bytes: %u frames (%u segments, %u "
	       "sent again), %zu bytes of slcan lines to the robot, %zu "
	       "replies (%zu bytes) back\n",
	       len, t.frames, t.total, t.resent_segments, out_bytes, replies,
	       in_bytes);
	printf("                  %.3f s at 115,200 baud (%.0f image bytes/s); "
	       "%.3f s wall time under QEMU (M3, its emulated UART)\n",
	       (double)out_bytes / line_bytes_per_s,
	       (double)len / ((double)out_bytes / line_bytes_per_s), wall);
	return 0;
}

int main(int argc, char **argv)
{
	size_t ticks = 2000;
	for (int i = 1; i < argc; i++) {
		if (strcmp(argv[i], "--ticks") == 0 && i + 1 < argc) {
			long long n;
			if (bench_ticks_arg("bench_firmware", argv[++i], &n))
				return 2;
			ticks = (size_t)n;
		} else {
			fprintf(stderr, "usage: bench_firmware [--ticks N]\n");
			return 2;
		}
	}
	if (getenv("EVO_BUILD"))
		build = getenv("EVO_BUILD");
	char path[512], err[512];
	snprintf(path, sizeof path, "%s/firmware/mind/run.trace", build);
	if (trace_load(path, &trace, err, sizeof err) != 0) {
		fprintf(stderr, "bench_firmware: %s\n", err);
		return 1;
	}
	if (ticks == 0 || ticks > trace.n_ticks)
		ticks = trace.n_ticks;
	snprintf(path, sizeof path, "minds/%s", trace.mind);
	int same = 0;
	double ns = host_ns_per_tick(path, ticks, &same);
	unsigned long marks = 0;
	double wire = 0;
	double insns = m3_insns_per_tick(ticks, &wire, &marks);
	printf("bench_firmware: the %s hierarchy, %zu ticks of %s\n",
	       trace.mind, ticks, "its recorded trace");
	if (ns > 0)
		printf("  host:           %8.1f ns per tick (evo_mind_step, "
		       "best of 5)%s\n",
		       ns, same ? "" : "  ACTUATORS DIFFER FROM THE TRACE");
	if (insns > 0)
		printf("  Cortex-M3:      %8.1f instructions per tick in the "
		       "MIND runtime (QEMU, %lu ticks counted)\n",
		       insns, marks);
	if (insns > 0)
		printf(
		    "                  %8.1f more per tick in the CAN frames "
		    "and slcan lines (core/src/wire.c), counted apart\n",
		    wire);
	int flashed = flash_over_slcan();
	trace_free(&trace);
	return ns > 0 && same && insns > 0 && flashed == 0 ? 0 : 1;
}
