/* The Makefile's rules a user meets: `make firmware` builds again for
 * another FW_MIND or FW_BOT (firmware/firmware.mk) instead of keeping the
 * images and objects of the earlier mind, and going back builds again too;
 * `make install` installs the example minds and the docs beside lua/
 * under PREFIX/share/evo. Each make runs in a build folder of its own
 * (BUILD=tmp), with the evo under test (FW_EVO, install-files). */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/fileio.h"
#include "harness.h"
#include "support/cli.h"

static char out[16384];

/* make [vars] TARGET in the build folder tmp/b, quietly; its status. */
static int fw_make(const char *vars, const char *target)
{
	return cli_capture(out, sizeof out,
			   "env -u MAKEFLAGS -u MFLAGS make --no-print-directory "
			   "BUILD=%s/b FW_EVO=%s "
			   "%s %s/b/firmware/%s 2>&1",
			   cli_tmp, cli_evo, vars, cli_tmp, target);
}

#define AVOID "FW_MIND=minds/Avoid FW_OTHER_MIND=minds/Collect"

TEST(firmware_builds_again_for_another_mind_or_bot)
{
	/* the exported mind the firmware carries */
	CHECK_EQ_INT(fw_make("", "mind/mind.h"), 0);
	char *h = cli_read("%s/b/firmware/mind/mind.h", cli_tmp);
	CHECK_CONTAINS(h, "Mind image of Collect (");
	free(h);
	/* another mind: its image, not the one built before */
	CHECK_EQ_INT(fw_make(AVOID, "mind/mind.h"), 0);
	h = cli_read("%s/b/firmware/mind/mind.h", cli_tmp);
	CHECK(h && strstr(h, "Mind image of Avoid ("));
	free(h);
	/* and back: Collect's again */
	CHECK_EQ_INT(fw_make("", "mind/mind.h"), 0);
	h = cli_read("%s/b/firmware/mind/mind.h", cli_tmp);
	CHECK(h && strstr(h, "Mind image of Collect ("));
	free(h);
	/* the same values again: nothing to do */
	CHECK_EQ_INT(fw_make("", "mind/mind.h"), 0);
	CHECK(strstr(out, "evo export") == NULL && strstr(out, "mind.h") == NULL);
	/* an object compiled with the robot's names: another FW_BOT
	 * compiles it again */
	if (cli_sh("command -v arm-none-eabi-gcc >/dev/null") != 0) {
		printf("  (no arm-none-eabi-gcc: the object part is skipped)\n");
		return;
	}
	CHECK_EQ_INT(fw_make("", "m3/mind_slot.o"), 0);
	CHECK_EQ_INT(fw_make("", "m3/mind_slot.o"), 0);
	CHECK(strstr(out, "mind_slot.c") == NULL);
	CHECK_EQ_INT(fw_make("FW_BOT=Other", "m3/mind_slot.o"), 0);
	CHECK_CONTAINS(out, "arm-none-eabi-gcc");
	CHECK_CONTAINS(out, "mind_slot.c");
}

TEST(install_puts_the_minds_and_the_docs_beside_lua)
{
	int rc = cli_capture(out, sizeof out,
			     "env -u MAKEFLAGS -u MFLAGS make -s --no-print-directory "
			     "install-files "
			     "BUILD=$(dirname %s) PREFIX=%s/usr 2>&1",
			     cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	if (rc)
		printf("%s\n", out);
	char path[512];
	const char *want[] = {"bin/evo", "share/evo/lua/learn/neat.lua",
			      "share/evo/minds/Avoid/Avoid.botdesc",
			      "share/evo/minds/Avoid/Tasks/Avoid-NEAT.simbatch",
			      "share/evo/docs/learning.md"};
	for (size_t i = 0; i < sizeof want / sizeof *want; i++) {
		snprintf(path, sizeof path, "%s/usr/%s", cli_tmp, want[i]);
		CHECK(evo_file_exists(path));
		if (!evo_file_exists(path))
			printf("  missing: %s\n", path);
	}
	/* the installed evo runs an installed example */
	CHECK_EQ_INT(cli_sh("cp -r %s/usr/share/evo/minds/Avoid %s/Avoid && "
			    "%s/usr/bin/evo check %s/Avoid/Tasks/"
			    "Avoid-NEAT.simbatch > /dev/null",
			    cli_tmp, cli_tmp, cli_tmp, cli_tmp),
		     0);
}

int main(void)
{
	if (cli_setup("make-rules"))
		return 1;
	RUN(firmware_builds_again_for_another_mind_or_bot);
	RUN(install_puts_the_minds_and_the_docs_beside_lua);
	cli_cleanup();
	return test_summary();
}
