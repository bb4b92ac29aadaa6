/* A QEMU TCG plugin that counts the guest instructions executed in each
 * of a few address ranges, from the first time a marker address runs, and
 * how many times that marker ran. bench/bench_firmware.c loads it with the
 * ranges of the MIND runtime's code and of the slcan code, and the marker
 * evo_mind_step, which gives the instructions per tick in each.
 *
 *   qemu-system-arm ... -plugin insn_count.so,lo=0x..,hi=0x..,mark=0x..,out=FILE
 *   (another range: lo=0x..,hi=0x.. again, before or after mark= and out=)
 *
 * Each lo= starts a range [lo, hi), up to MAX_RANGES; ranges should not
 * overlap (an instruction counts in the first that holds it). At exit it
 * writes one line to FILE, a count for each range in the order given:
 *   insns TOTAL marks MARKS range SINCE_MARK [range SINCE_MARK ...]
 * TOTAL counts every instruction. One vCPU is assumed (the Cortex-M
 * boards have one), so the counters need no atomics. */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "qemu_plugin_api.h"

QEMU_PLUGIN_EXPORT int qemu_plugin_version = QEMU_PLUGIN_VERSION;
QEMU_PLUGIN_EXPORT int qemu_plugin_install(qemu_plugin_id_t id,
					   const qemu_info_t *info, int argc,
					   char **argv);

#define MAX_RANGES 4

static struct {
	uint64_t lo, hi;
	uint64_t count, count_at_mark;
} ranges[MAX_RANGES];
static unsigned n_ranges;
static uint64_t mark, total, marks;
static char out_path[1024];

/* Runs before the marker instruction's own count is added. */
static void on_mark(unsigned int vcpu, void *udata)
{
	(void)vcpu;
	(void)udata;
	if (marks++ == 0)
		for (unsigned r = 0; r < n_ranges; r++)
			ranges[r].count_at_mark = ranges[r].count;
}

static void on_tb(qemu_plugin_id_t id, struct qemu_plugin_tb *tb)
{
	(void)id;
	size_t n = qemu_plugin_tb_n_insns(tb);
	qemu_plugin_register_vcpu_tb_exec_inline(tb, QEMU_PLUGIN_INLINE_ADD_U64,
						 &total, n);
	for (size_t i = 0; i < n; i++) {
		struct qemu_plugin_insn *insn = qemu_plugin_tb_get_insn(tb, i);
		uint64_t pc = qemu_plugin_insn_vaddr(insn);
		if (pc == mark)
			qemu_plugin_register_vcpu_insn_exec_cb(
				insn, on_mark, QEMU_PLUGIN_CB_NO_REGS, NULL);
		for (unsigned r = 0; r < n_ranges; r++) {
			if (pc >= ranges[r].lo && pc < ranges[r].hi) {
				qemu_plugin_register_vcpu_insn_exec_inline(
					insn, QEMU_PLUGIN_INLINE_ADD_U64,
					&ranges[r].count, 1);
				break;
			}
		}
	}
}

static void on_exit(qemu_plugin_id_t id, void *udata)
{
	(void)id;
	(void)udata;
	char line[64 + 32 * MAX_RANGES];
	size_t len = (size_t)snprintf(line, sizeof line,
				      "insns %" PRIu64 " marks %" PRIu64,
				      total, marks);
	for (unsigned r = 0; r < n_ranges; r++)
		len += (size_t)snprintf(
			line + len, sizeof line - len, " range %" PRIu64,
			marks ? ranges[r].count - ranges[r].count_at_mark : 0);
	snprintf(line + len, sizeof line - len, "\n");
	FILE *f = out_path[0] ? fopen(out_path, "w") : NULL;
	if (f) {
		fputs(line, f);
		fclose(f);
	} else {
		fputs(line, stderr);
	}
}

static int arg_u64(const char *arg, const char *key, uint64_t *v)
{
	size_t k = strlen(key);
	if (strncmp(arg, key, k) != 0 || arg[k] != '=')
		return 0;
	char *end;
	*v = strtoull(arg + k + 1, &end, 0);
	return *end == 0 && end != arg + k + 1 ? 1 : -1;
}

int qemu_plugin_install(qemu_plugin_id_t id, const qemu_info_t *info,
			int argc, char **argv)
{
	(void)info;
	for (int i = 0; i < argc; i++) {
		const char *a = argv[i];
		uint64_t v;
		int r = 0;
		if (strncmp(a, "out=", 4) == 0) {
			snprintf(out_path, sizeof out_path, "%s", a + 4);
			r = 1;
		} else if ((r = arg_u64(a, "lo", &v)) != 0) {
			/* A lo= opens the next range; its hi= must follow. */
			if (r == 1 && n_ranges < MAX_RANGES &&
			    (n_ranges == 0 || ranges[n_ranges - 1].hi != 0))
				ranges[n_ranges++].lo = v;
			else
				r = -1;
		} else if ((r = arg_u64(a, "hi", &v)) != 0) {
			if (r == 1 && n_ranges > 0 &&
			    ranges[n_ranges - 1].hi == 0 &&
			    v > ranges[n_ranges - 1].lo)
				ranges[n_ranges - 1].hi = v;
			else
				r = -1;
		} else {
			r = arg_u64(a, "mark", &mark);
		}
		if (r != 1) {
			fprintf(stderr,
				"insn_count: unknown or bad argument '%s' "
				"(lo=ADDR,hi=ADDR for each of up to %d "
				"ranges, mark=ADDR, out=FILE)\n",
				a, MAX_RANGES);
			return -1;
		}
	}
	if (n_ranges == 0 || ranges[n_ranges - 1].hi == 0) {
		fprintf(stderr, "insn_count: no range, or a lo= without its "
				"hi= (lo=ADDR,hi=ADDR)\n");
		return -1;
	}
	qemu_plugin_register_vcpu_tb_trans_cb(id, on_tb);
	qemu_plugin_register_atexit_cb(id, on_exit, NULL);
	return 0;
}
