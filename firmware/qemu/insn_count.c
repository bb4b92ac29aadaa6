/* A QEMU TCG plugin that counts the guest instructions executed in an
 * address range, from the first time a marker address runs, and how many
 * times that marker ran. bench/bench_firmware.c loads it with the range of
 * the MIND runtime's code and the marker evo_mind_step, which gives the
 * instructions per tick.
 *
 *   qemu-system-arm ... -plugin insn_count.so,lo=0x..,hi=0x..,mark=0x..,out=FILE
 *
 * At exit it writes one line to FILE:
 *   insns TOTAL range RANGE_SINCE_MARK marks MARKS
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

static uint64_t lo, hi, mark;
static uint64_t total, in_range, in_range_at_mark, marks;
static char out_path[1024];

/* Runs before the marker instruction's own count is added. */
static void on_mark(unsigned int vcpu, void *udata)
{
	(void)vcpu;
	(void)udata;
	if (marks++ == 0)
		in_range_at_mark = in_range;
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
		if (pc >= lo && pc < hi)
			qemu_plugin_register_vcpu_insn_exec_inline(
				insn, QEMU_PLUGIN_INLINE_ADD_U64, &in_range, 1);
	}
}

static void on_exit(qemu_plugin_id_t id, void *udata)
{
	(void)id;
	(void)udata;
	char line[160];
	snprintf(line, sizeof line,
		 "insns %" PRIu64 " range %" PRIu64 " marks %" PRIu64 "\n",
		 total, marks ? in_range - in_range_at_mark : 0, marks);
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
		int r = 0;
		if (strncmp(a, "out=", 4) == 0) {
			snprintf(out_path, sizeof out_path, "%s", a + 4);
			r = 1;
		} else if ((r = arg_u64(a, "lo", &lo)) == 0 &&
			   (r = arg_u64(a, "hi", &hi)) == 0) {
			r = arg_u64(a, "mark", &mark);
		}
		if (r != 1) {
			fprintf(stderr,
				"insn_count: unknown or bad argument '%s' "
				"(lo=ADDR, hi=ADDR, mark=ADDR, out=FILE)\n",
				a);
			return -1;
		}
	}
	qemu_plugin_register_vcpu_tb_trans_cb(id, on_tb);
	qemu_plugin_register_atexit_cb(id, on_exit, NULL);
	return 0;
}
