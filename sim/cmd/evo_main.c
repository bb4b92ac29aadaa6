/* The evo command. `evo help` lists what it does. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "base/err.h"
#include "base/fileio.h"
#include "base/number.h"
#include "cmd/export_c.h"
#include "cmd/flash.h"
#include "cmd/mindinfo.h"
#include "cmd/info_dot.h"
#include "cmd/run.h"
#include "cmd/serve.h"
#include "learn/learn.h"
#include "learn/literature.h"
#include "mind/mindfolder.h"
#include "mind/task.h"
#include "remote/robot.h"
#include "tasksim/tasksim.h"

#include <lua.h>

/* evo's version: the part of the project it was built at. */
#define EVO_VERSION "0.16"

/* Each command's lines of `evo help`, and what `evo CMD --help` prints
 * for the commands that have no page of their own. */
static const struct {
	const char *cmd, *text;
} command_help[] = {
    {"", "  evo [-nog] TASK.simbatch   the tutorial's form of evo run\n"},
    {"run", "  evo run TASK.simbatch [--headless|-nog] [--seed N]\n"
	    "          [--episodes N] [--ticks N] [--trace FILE]\n"
	    "      run a task: DEMOSIM in the viewer, or headless;\n"
	    "      LEARNSIM trains (--threads N, --run DIR, --resume),\n"
	    "      LEARNSIMCONTINUOUS every skill of the hierarchy in turn;\n"
	    "      DEMO2DSIMMULTI and LEARN2DSIMMULTI do so with teams\n"
	    "      (docs/teams.md), DEMO3DSIM and LEARN3DSIM in the 3D\n"
	    "      world on ODE (docs/world3d.md), DEMO3DSIMMULTI and\n"
	    "      LEARN3DSIMMULTI with teams there; under mpirun -np N,\n"
	    "      LEARNSIM and OPENENDED spread over N processes\n"
	    "      (docs/cluster.md)\n"
	    "      (evo run --help lists every option);\n"
	    "      DEMOREMOTESIM drives a remote simulator over LCM,\n"
	    "      DEMOREMOTE a robot over LCM or, with --can URL, CAN\n"},
    {"serve", "  evo serve TASK.simbatch [--name NAME] [--environments N]\n"
	      "          [--robot [--tick-ms MS] [--timeout S]] [--can URL]\n"
	      "      serve the task's 2D world as a remote simulator over\n"
	      "      LCM, or as a stand-in robot in real time, over LCM or\n"
	      "      as a body on a CAN bus, until stopped (docs/remote.md,\n"
	      "      docs/can.md)\n"},
    {"info", "  evo info MINDFOLDER|IMAGE.bin [--master SKILL]\n"
	     "           [--net SKILL=NET ...] [--dot [SKILL]]\n"
	     "           [-o FILE.dot|FILE.png|FILE.svg]\n"
	     "      load a mind folder (or an exported image) and show its\n"
	     "      hierarchy in tick order, and which skills have no\n"
	     "      network yet, in the order to train them; --dot draws\n"
	     "      the hierarchy, or with SKILL that skill's network, as\n"
	     "      Graphviz DOT (on stdout, or in FILE; .png and .svg are\n"
	     "      rendered by Graphviz's dot; docs/running.md)\n"},
    {"check", "  evo check TASK.simbatch [--net SKILL=NET ...]\n"
	      "      check a task file, the mind folder it names, its bot\n"
	      "      model and environment, and, for LEARNSIM, the learning\n"
	      "      method's options\n"},
    {"tick", "  evo tick MINDFOLDER|IMAGE.bin [--master SKILL] [--ticks N]\n"
	     "           [--sensor NAME=VALUE ...] [--net SKILL=NET ...]\n"
	     "      run the mind for N ticks (default 10) on fixed sensor\n"
	     "      values (default 0.5) and print actuators and influences\n"},
    {"export", "  evo export MINDFOLDER [--master SKILL] [--format bin|c]\n"
	       "             [-o FILE]\n"
	       "      write the mind image (default MINDFOLDER/mind.bin), or\n"
	       "      with --format c a C header of it for a firmware\n"
	       "      (default MINDFOLDER/mind.h)\n"},
    {"flash", "  evo flash MINDFOLDER|IMAGE.bin --can URL [--master SKILL]\n"
	      "            [--window N] [--wait MS] [--tries N]\n"
	      "      send the mind image to a robot's running firmware over\n"
	      "      CAN; it switches to it between two ticks, or refuses it\n"
	      "      and keeps its mind (docs/firmware.md)\n"},
    {"version", "  evo version, evo --version\n"
		"      print evo's version and the Lua it runs\n"},
    {"help", "  evo help [COMMAND], evo COMMAND --help\n"
	     "      this text, or one command's\n"},
};

#define N_COMMANDS (sizeof command_help / sizeof command_help[0])

static void usage(FILE *f)
{
	fputs("usage:\n", f);
	for (size_t i = 0; i < N_COMMANDS; i++)
		fputs(command_help[i].text, f);
}

/* `evo CMD --help` and `evo help CMD`: the command's own page on stdout;
 * 0, or 2 for a command evo does not have. */
static int command_usage(const char *cmd)
{
	if (strcmp(cmd, "run") == 0)
		evo_run_usage(stdout);
	else if (strcmp(cmd, "serve") == 0)
		evo_serve_usage(stdout);
	else if (strcmp(cmd, "flash") == 0)
		evo_flash_usage(stdout);
	for (size_t i = 1; i < N_COMMANDS; i++)
		if (strcmp(cmd, command_help[i].cmd) == 0) {
			if (strcmp(cmd, "run") && strcmp(cmd, "serve") &&
			    strcmp(cmd, "flash"))
				printf("usage:\n%s", command_help[i].text);
			return 0;
		}
	fprintf(stderr, "evo: unknown command '%s'\n", cmd);
	usage(stderr);
	return 2;
}

static int is_help(const char *a)
{
	return strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0;
}

static int version(void)
{
	printf("evo %s\n%s\n", EVO_VERSION, LUA_RELEASE);
	return 0;
}

static const char *kind_name(const evo_ades *a)
{
	return a->kind == EVO_SKILL_NEURAL ? "neural" : "hardCoded";
}

static int cmd_info(const evo_mindfolder *l)
{
	const evo_mind *m = &l->mind;
	printf("mind %s: %u sensors, %u actuators, %u variables, %u skills\n",
	       l->bot_name, m->n_sensors, m->n_actuators, m->n_vars,
	       m->n_skills);
	printf("tick order (master first, parents before sub-skills):\n");
	for (unsigned i = 0; i < l->n_skills; i++) {
		const evo_ades *a = &l->skill[i];
		printf("  %2u %-16s %-9s in %-2u out %-2u", i, a->name,
		       kind_name(a), a->n_in, a->n_out);
		if (a->kind == EVO_SKILL_HARDCODED)
			printf(" class:%s", a->hc_class);
		else if (l->untrained && l->untrained[i] == 2)
			printf(" network: none yet, this task trains it");
		else if (l->untrained && l->untrained[i])
			printf(" network: none yet");
		else
			printf(" network: %u nodes, %u links",
			       (unsigned)(l->net[i]->n_in + l->net[i]->n_nodes),
			       (unsigned)l->net[i]->n_links);
		int first = 1;
		for (unsigned j = 0; j < a->n_out; j++)
			if (a->out[j].type == EVO_OUT_SK) {
				printf("%s%s", first ? " -> " : ", ",
				       a->out[j].name);
				first = 0;
			}
		printf("\n");
	}
	if (evo_untrained_report(l, stdout))
		printf("mind image (untrained skills with zero weights): %zu "
		       "bytes; mind state: %zu bytes\n",
		       l->image_len, evo_state_size(m));
	else
		printf("mind image: %zu bytes; mind state: %zu bytes\n",
		       l->image_len, evo_state_size(m));
	return 0;
}

/* evo info --dot [SKILL] [-o FILE]: the hierarchy or SKILL's network as
 * DOT, on stdout or in FILE (rendered when FILE is not .dot). */
static int cmd_dot(const evo_mindfolder *l, const char *skill,
		   const char *out)
{
	int k = -1;
	evo_err err = {{0}};
	if (skill && (k = evo_mindfolder_skill(l, skill)) < 0) {
		fprintf(stderr, "evo info --dot %s: %s has no skill '%s' (its "
				"skills:",
			skill, l->root, skill);
		for (unsigned i = 0; i < l->n_skills; i++)
			fprintf(stderr, " %s", l->skill[i].name);
		fprintf(stderr, ")\n");
		return 1;
	}
	int rc = 0;
	if (k >= 0 && l->untrained && l->untrained[k])
		fprintf(stderr,
			"evo info --dot %s: %s has no network yet; this is its "
			"shape, every weight 0\n",
			skill, skill);
	if (out) {
		rc = evo_dot_write(out, l, k, &err);
		if (rc == 0)
			printf("%s: %s of %s\n", out,
			       k < 0 ? "the hierarchy" : "the network",
			       k < 0 ? l->root : skill);
	} else if (k < 0) {
		evo_dot_hierarchy(stdout, l);
	} else {
		rc = evo_dot_net(stdout, l, (unsigned)k, &err);
	}
	if (rc)
		fprintf(stderr, "%s\n", err.msg);
	return rc ? 1 : 0;
}

/* --sensor NAME=VALUE into values; where names the sensors' source
 * ("Avoid.botdesc", or the image file) in a message. */
static int set_sensor(const evo_mind *m, const char *where, const char *arg,
		      double *values)
{
	const char *eq = strchr(arg, '=');
	char *end;
	if (!eq)
		return fprintf(stderr,
			       "evo: --sensor expects NAME=VALUE, found '%s'\n",
			       arg),
		       -1;
	double v = strtod(eq + 1, &end);
	/* Written so that NaN fails too: nan and inf are refused here rather
	 * than mapped (docs/mind.md, "Sensor values"). */
	if (end == eq + 1 || *end || !(v >= 0 && v <= 1))
		return fprintf(stderr,
			       "evo: --sensor %s: the value of sensor '%.*s' "
			       "must be a number in [0, 1]\n",
			       arg, (int)(eq - arg), arg),
		       -1;
	for (unsigned i = 0; i < m->n_sensors; i++)
		if (strlen(evo_mind_sensor_name(m, i)) == (size_t)(eq - arg) &&
		    strncmp(evo_mind_sensor_name(m, i), arg,
			    (size_t)(eq - arg)) == 0) {
			values[i] = v;
			return 0;
		}
	fprintf(stderr, "evo: --sensor %s: %s has no sensor '%.*s'\n", arg,
		where, (int)(eq - arg), arg);
	return -1;
}

static int cmd_tick(const evo_mind *m, long ticks, double *sensor_values)
{
	size_t size = evo_state_size(m);
	void *mem = aligned_alloc(8, (size + 7) & ~(size_t)7);
	evo_q16 sensors[EVO_MAX_SENSORS], actuators[EVO_MAX_ACTUATORS];
	evo_state *s;
	if (!mem || evo_state_init(m, mem, size, &s) != EVO_OK) {
		free(mem);
		fprintf(stderr, "evo: cannot set up the mind state\n");
		return 1;
	}
	for (unsigned i = 0; i < m->n_sensors; i++)
		sensors[i] = evo_q16_from_sensor(sensor_values[i]);
	printf("tick");
	for (unsigned a = 0; a < m->n_actuators; a++)
		printf(" %8s", evo_mind_actuator_name(m, a));
	for (unsigned v = 0; v < m->n_vars; v++)
		printf(" %8s", evo_mind_var_name(m, v));
	printf("  influences\n");
	for (long t = 0; t < ticks; t++) {
		evo_mind_step(m, s, sensors, actuators);
		printf("%4ld", t);
		for (unsigned a = 0; a < m->n_actuators; a++)
			printf(" %8.4f", evo_q16_to_double(actuators[a]));
		for (unsigned v = 0; v < m->n_vars; v++)
			printf(" %8.4f", evo_q16_to_double(s->var[v].value));
		printf(" ");
		for (unsigned i = 0; i < m->n_skills; i++)
			printf(" %s=%.2f", evo_mind_skill_name(m, i),
			       evo_q16_to_double(s->influence[i]));
		printf("\n");
	}
	free(mem);
	return 0;
}

/* evo info and evo tick of an exported mind image (.bin): its own names
 * say what it holds. --master and --net need the mind folder. */
static int image_cmd(const char *cmd, const char *path, long ticks,
		     const char *const *sensor_args, unsigned n_sensor_args,
		     int folder_opts)
{
	if (folder_opts) {
		fprintf(stderr,
			"evo %s: %s is a mind image, made for one master "
			"with its networks: --master and --net need the mind "
			"folder\n",
			cmd, path);
		return 2;
	}
	evo_err err = {{0}};
	evo_mind m;
	void *buf;
	if (evo_image_load(path, &buf, &m, &err)) {
		fprintf(stderr, "%s\n", err.msg);
		return 1;
	}
	int rc = 0;
	if (strcmp(cmd, "info") == 0) {
		evo_image_info(path, &m);
	} else {
		double values[EVO_MAX_SENSORS];
		for (unsigned i = 0; i < EVO_MAX_SENSORS; i++)
			values[i] = 0.5;
		for (unsigned i = 0; i < n_sensor_args && rc == 0; i++)
			rc = set_sensor(&m, path, sensor_args[i], values) ? 2
									  : 0;
		if (rc == 0)
			rc = cmd_tick(&m, ticks, values);
	}
	free(buf);
	return rc;
}

/* A path ending in .simbatch (any case). */
static int is_task_path(const char *a)
{
	size_t n = strlen(a);
	return n > 9 && strcasecmp(a + n - 9, ".simbatch") == 0;
}

int main(int argc, char **argv)
{
	if (argc < 2 || strcmp(argv[1], "help") == 0 || is_help(argv[1])) {
		if (argc == 3 && strcmp(argv[1], "help") == 0)
			return command_usage(argv[2]);
		usage(argc < 2 ? stderr : stdout);
		return argc < 2 ? 2 : 0;
	}
	const char *cmd = argv[1];
	if (strcmp(cmd, "version") == 0 || strcmp(cmd, "--version") == 0)
		return version();
	/* `evo CMD ... --help` anywhere: the command's page, not an error
	 * about its other arguments ("not a mind folder") */
	int tutorial = strcmp(cmd, "-nog") == 0 ||
		       strcmp(cmd, "--headless") == 0 || is_task_path(cmd);
	for (int i = 2; i < argc; i++)
		if (is_help(argv[i]))
			return command_usage(tutorial ? "run" : cmd);
	evo_err err = {{0}};
	if (strcmp(cmd, "run") == 0)
		return evo_run_main(argc, argv);
	if (strcmp(cmd, "serve") == 0)
		return evo_serve_main(argc, argv);
	if (strcmp(cmd, "flash") == 0)
		return evo_flash_main(argc, argv);
	/* The tutorial's command line: `evo TASK.simbatch` and
	 * `evo -nog TASK.simbatch` are `evo run` with the same arguments. */
	if (tutorial) {
		char **run_argv = calloc((size_t)argc + 2, sizeof *run_argv);
		if (!run_argv) {
			fprintf(stderr, "evo: out of memory\n");
			return 1;
		}
		run_argv[0] = argv[0];
		run_argv[1] = "run";
		for (int i = 1; i < argc; i++)
			run_argv[i + 1] = argv[i];
		int rc = evo_run_main(argc + 1, run_argv);
		free(run_argv);
		return rc;
	}
	if (strcmp(cmd, "check") == 0) {
		/* --net SKILL=NET ..., as evo run takes them */
		evo_net_choice nets[16];
		char skills[16][EVO_NAME_MAX];
		unsigned n_nets = 0;
		for (int i = 3; i < argc; i += 2) {
			const char *v = i + 1 < argc ? argv[i + 1] : "";
			const char *eq = strchr(v, '=');
			if (strcmp(argv[i], "--net") != 0 || !eq || eq == v ||
			    !eq[1] || (size_t)(eq - v) >= EVO_NAME_MAX ||
			    n_nets == 16) {
				usage(stderr);
				return 2;
			}
			snprintf(skills[n_nets], EVO_NAME_MAX, "%.*s",
				 (int)(eq - v), v);
			nets[n_nets] = (evo_net_choice){skills[n_nets], eq + 1};
			n_nets++;
		}
		if (argc < 3) {
			usage(stderr);
			return 2;
		}
		evo_task task;
		evo_task_opts to = {
		    .untrained_ok = 1, .nets = nets, .n_nets = n_nets};
		if (evo_task_load_opts(argv[2], &to, &task, &err) != 0) {
			fprintf(stderr, "%s\n", err.msg);
			return 1;
		}
		if (evo_task_check(argv[2], &task, &err) != 0) {
			fprintf(stderr, "%s\n", err.msg);
			evo_task_free(&task);
			return 1;
		}
		if (task.n_teams == 0 && evo_untrained_count(task.mind)) {
			printf("%s: task %s, mind folder %s: not ready to run "
			       "until the skills below are trained\n",
			       argv[2], task.type, task.mind->root);
			cmd_info(task.mind);
			evo_task_free(&task);
			return 1;
		}
		/* a warning is most often a misspelt key, which evo run
		 * would ignore: evo check, which is asked to find such
		 * things, ends with the count and fails */
		unsigned warned = evo_warning_count();
		char verdict[160] = "ok";
		if (warned)
			snprintf(verdict, sizeof verdict,
				 "not ok, %u warning%s above (evo run would "
				 "run it without what %s)",
				 warned, warned == 1 ? "" : "s",
				 warned == 1 ? "it names" : "they name");
		if (task.n_teams == 0)
			printf("%s: task %s, mind folder %s, master skill %s: "
			       "%s\n",
			       argv[2], task.type, task.mind->root,
			       evo_mind_skill_name(&task.mind->mind, 0),
			       verdict);
		else
			printf("%s: task %s, %d team%s: %s\n", argv[2],
			       task.type, task.n_teams,
			       task.n_teams == 1 ? "" : "s", verdict);
		for (int i = 0; i < task.n_teams; i++)
			printf("  team %s: %d bot%s of %s, mind folder %s, "
			       "master skill %s\n",
			       task.team[i].name, task.team[i].size,
			       task.team[i].size == 1 ? "" : "s",
			       task.team[i].botmodel, task.team[i].mind->root,
			       task.team[i].master);
		evo_task_free(&task);
		return warned ? 1 : 0;
	}
	if (strcmp(cmd, "info") != 0 && strcmp(cmd, "tick") != 0 &&
	    strcmp(cmd, "export") != 0) {
		fprintf(stderr, "evo: unknown command '%s'\n", cmd);
		usage(stderr);
		return 2;
	}
	if (argc < 3) {
		usage(stderr);
		return 2;
	}
	evo_mindfolder_opts opts = {0};
	long ticks = 10;
	const char *out = NULL;
	int format_c = 0;
	int dot = 0;		  /* evo info --dot */
	const char *dot_skill = NULL; /* its SKILL, if one is named */
	const char *sensor_args[EVO_MAX_SENSORS];
	unsigned n_sensor_args = 0;
	evo_net_choice nets[16];
	char net_skill[16][EVO_NAME_MAX];
	unsigned n_nets = 0;
	for (int i = 3; i < argc; i++) {
		const char *a = argv[i];
		const char *v = i + 1 < argc ? argv[i + 1] : NULL;
		if (strcmp(a, "--master") == 0 && v) {
			opts.master = v;
			i++;
		} else if (strcmp(a, "--ticks") == 0 && v) {
			/* digits only: 99999999999999999999 was LONG_MAX,
			 * a run that never ends */
			long long n;
			if (evo_parse_whole(v, NULL, 0, 1000000000, &n)) {
				fprintf(stderr,
					"evo: --ticks expects a whole number "
					"0..1000000000, found '%s'\n",
					v);
				return 2;
			}
			ticks = (long)n;
			i++;
		} else if (strcmp(a, "--sensor") == 0 && v &&
			   n_sensor_args < EVO_MAX_SENSORS) {
			sensor_args[n_sensor_args++] = v;
			i++;
		} else if (strcmp(a, "--net") == 0 && v &&
			   strcmp(cmd, "export") != 0 && n_nets < 16) {
			/* SKILL=FILE|random|zero, as evo run --net */
			const char *eq = strchr(v, '=');
			if (!eq || eq == v || !eq[1] ||
			    (size_t)(eq - v) >= EVO_NAME_MAX) {
				fprintf(stderr,
					"evo %s: --net expects SKILL=FILE, "
					"SKILL=random or SKILL=zero, found "
					"'%s'\n",
					cmd, v);
				return 2;
			}
			snprintf(net_skill[n_nets], EVO_NAME_MAX, "%.*s",
				 (int)(eq - v), v);
			nets[n_nets].skill = net_skill[n_nets];
			nets[n_nets++].source = eq + 1;
			i++;
		} else if (strcmp(a, "--dot") == 0 && strcmp(cmd, "info") == 0) {
			dot = 1;
			if (v && v[0] != '-') {
				dot_skill = v;
				i++;
			}
		} else if (strcmp(a, "-o") == 0 && v &&
			   strcmp(cmd, "tick") != 0) {
			out = v;
			i++;
		} else if (strcmp(a, "--format") == 0 && v &&
			   strcmp(cmd, "export") == 0) {
			if (strcmp(v, "c") != 0 && strcmp(v, "bin") != 0) {
				fprintf(stderr,
					"evo export: --format expects bin or c, "
					"found '%s'\n",
					v);
				return 2;
			}
			format_c = strcmp(v, "c") == 0;
			i++;
		} else {
			fprintf(stderr, "evo %s: unexpected argument '%s'\n",
				cmd, a);
			usage(stderr);
			return 2;
		}
	}
	if (dot && evo_is_image_path(argv[2])) {
		fprintf(stderr,
			"evo info --dot: %s is an exported image; --dot draws "
			"a mind folder\n",
			argv[2]);
		return 2;
	}
	if (strcmp(cmd, "export") != 0 && evo_is_image_path(argv[2]))
		return image_cmd(cmd, argv[2], ticks, sensor_args,
				 n_sensor_args, opts.master || n_nets);
	opts.nets = nets;
	opts.n_nets = n_nets;
	/* a hierarchy can be looked at before its sub-skills are trained */
	opts.untrained_ok = strcmp(cmd, "info") == 0;
	evo_mindfolder *l = evo_mindfolder_load(argv[2], &opts, &err);
	if (!l) {
		fprintf(stderr, "%s\n", err.msg);
		return 1;
	}
	int rc = 0;
	if (strcmp(cmd, "info") == 0 && out && !dot) {
		fprintf(stderr, "evo info: -o FILE is for --dot\n");
		rc = 2;
	} else if (strcmp(cmd, "info") == 0 && dot) {
		rc = cmd_dot(l, dot_skill, out);
	} else if (strcmp(cmd, "info") == 0) {
		rc = cmd_info(l);
	} else if (strcmp(cmd, "tick") == 0) {
		double values[EVO_MAX_SENSORS];
		char where[300];
		snprintf(where, sizeof where, "%s.botdesc", l->bot_name);
		for (unsigned i = 0; i < EVO_MAX_SENSORS; i++)
			values[i] = 0.5;
		for (unsigned i = 0; i < n_sensor_args && rc == 0; i++)
			rc = set_sensor(&l->mind, where, sensor_args[i], values)
				 ? 2
				 : 0;
		if (rc == 0)
			rc = cmd_tick(&l->mind, ticks, values);
	} else {
		char path[1200];
		if (!out) {
			snprintf(path, sizeof path, "%s/mind.%s", l->root,
				 format_c ? "h" : "bin");
			out = path;
		}
		size_t len = l->image_len;
		char *text = format_c ? evo_export_c(l, &len, &err) : NULL;
		if ((format_c && !text) ||
		    evo_write_file_atomic(out, format_c ? text : l->image, len,
					  &err) != 0) {
			fprintf(stderr, "%s\n", err.msg);
			rc = 1;
		} else {
			printf("%s: mind image of %s, %zu bytes%s\n", out,
			       l->bot_name, l->image_len,
			       format_c ? ", as a C header" : "");
		}
		free(text);
	}
	evo_mindfolder_free(l);
	return rc;
}
