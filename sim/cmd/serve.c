/* `evo serve TASK.simbatch`: evo's own world served as a remote
 * simulator over LCM (docs/remote.md): the 3D world of a DEMO3DSIM or
 * LEARN3DSIM task, the 2D world of any other. The task's environment and
 * bot model run here, reached through tasksim's evo_sim whichever world
 * it is; the mind runs in the `evo run` that drives it. This
 * file reads the options, loads the task, builds the hello, opens the
 * links and reports the drops at the end; serve_sim.c serves the
 * environments in lockstep, serve_robot.c stands in for a robot
 * (--robot), serve_can.c for a robot's body on a CAN bus (--can). */
#define _POSIX_C_SOURCE 200809L
#include "cmd/serve.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "base/counts.h"
#include "base/rng.h"
#include "cmd/serve_can.h"
#include "cmd/serve_internal.h"
#include "lua/lua_evo.h"
#include "mind/task.h"
#include "remote/session.h"

void evo_serve_usage(FILE *f)
{
	fputs(
	    "usage: evo serve TASK.simbatch [options]\n"
	    "  --name NAME         the name evo run finds it by (default\n"
	    "                      evo-serve-PID)\n"
	    "  --environments N    episodes run at once (default 1)\n"
	    "  --url URL           the LCM URL (default: the task's LCMURL,\n"
	    "                      else LCM's default)\n"
	    "  --data-url URL      the LCM URL of its episodes (default: the\n"
	    "                      URL on a port of its own, from its name;\n"
	    "                      'same': the URL itself)\n"
	    "  --key-file FILE     the key shared with evo run (default: the\n"
	    "                      task's LCMKEYFILE; docs/remote.md, Keys)\n"
	    "  --robot             stand in for a robot: run in real time and\n"
	    "                      go neutral when evo's commands stop\n"
	    "  --tick-ms MS        the robot's period (default 33.333: 30\n"
	    "                      ticks a second)\n"
	    "  --timeout S         seconds without a command before every\n"
	    "                      actuator goes neutral (default 0.5)\n"
	    "  --can URL           stand in for a robot's body on a CAN bus\n"
	    "                      instead (--robot's rules; socketcan:IFACE,\n"
	    "                      slcan-pty:[?link=PATH], "
	    "cannelloni:HOST:PORT\n"
	    "                      ...; docs/can.md)\n",
	    f);
}

/* The URL of a server's episodes: udpm://GROUP:PORT?OPTS on PORT + 1 +
 * (a hash of its name) % 2000, so that each server's traffic reaches
 * only evo and itself, not every other server on the URL (LCM over UDP
 * multicast hands every message on a port to every process listening on
 * it). Another kind of URL is used as it is. */
static void data_url_for(const char *url, const char *name, char *out,
			 size_t cap)
{
	const char *colon =
	    strncmp(url, "udpm://", 7) == 0 ? strchr(url + 7, ':') : NULL;
	char *end;
	long port = colon ? strtol(colon + 1, &end, 10) : -1;
	if (!colon || end == colon + 1 || port < 1 || port > 65535) {
		snprintf(out, cap, "%s", url);
		return;
	}
	uint32_t h = 2166136261u;
	for (const char *p = name; *p; p++)
		h = (h ^ (unsigned char)*p) * 16777619u;
	long own = port + 1 + (long)(h % 2000);
	if (own > 65535)
		own -= 4000;
	snprintf(out, cap, "%.*s:%ld%s", (int)(colon - url), url, own, end);
}

/* A session number no earlier run of this name is likely to have had. */
static int64_t new_session(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_REALTIME, &ts);
	evo_rng r = evo_rng_for((uint64_t)ts.tv_sec, (uint64_t)ts.tv_nsec,
				(uint64_t)getpid(), 0);
	return (int64_t)(evo_rng_next(&r) >> 1);
}

static const char *reason_name(int i)
{
	return evo_wire_reason_name((evo_wire_reason)i);
}

/* A remote task whose world failed to build: say after err's message
 * that its world was built 2D, as a 3D environment fails in the 2D world
 * with a message of its own (a 3D option unknown) that does not say so. */
static void say_which_world(const evo_task *task, const char *task_path,
			    evo_err *err)
{
	if (!strstr(task->type, "REMOTE"))
		return;
	size_t n = strlen(err->msg);
	snprintf(err->msg + n, sizeof err->msg - n,
		 "\nevo serve: %s is a %s task, served in the 2D world; a 3D "
		 "world is served from its DEMO3DSIM or LEARN3DSIM task, with "
		 "its ENV and BOTMODEL (docs/remote.md)",
		 task_path, task->type);
}

/* The variable of an LCM option a (--name, --url, --data-url,
 * --key-file: vars[0..3]), NULL for any other option. */
static const char **lcm_option(const char *a, const char **vars[4])
{
	static const char *const opts[4] = {"--name", "--url", "--data-url",
					    "--key-file"};
	for (int k = 0; k < 4; k++)
		if (strcmp(a, opts[k]) == 0)
			return vars[k];
	return NULL;
}

int evo_serve_main(int argc, char **argv)
{
	const char *task_path = NULL, *name = NULL, *url = NULL,
		   *data_url = NULL, *key_file = NULL;
	long envs = 1;
	int as_robot = 0, envs_set = 0;
	double tick_ms = 1000.0 / 30, timeout = 0.5;
	const char *robot_opt = NULL, *can_url = NULL, *lcm_opt = NULL;
	const char **lcm_vars[4] = {&name, &url, &data_url, &key_file};
	for (int i = 2; i < argc; i++) {
		const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
		if (strcmp(a, "--robot") == 0) {
			as_robot = 1;
		} else if (strcmp(a, "--can") == 0 && v) {
			can_url = v;
			as_robot = 1;
			i++;
		} else if ((strcmp(a, "--tick-ms") == 0 ||
			    strcmp(a, "--timeout") == 0) &&
			   v) {
			int is_tick = strcmp(a, "--tick-ms") == 0;
			double max = is_tick ? 60000 : 3600;
			char *end;
			double x = strtod(v, &end);
			if (*end || !(x > 0 && x <= max)) {
				fprintf(stderr,
					"evo serve: %s expects %s, more than 0 "
					"and at most %g, found '%s'\n",
					a, is_tick ? "milliseconds" : "seconds",
					max, v);
				return 2;
			}
			if (is_tick)
				tick_ms = x;
			else
				timeout = x;
			robot_opt = a;
			i++;
		} else if (v && lcm_option(a, lcm_vars)) {
			*lcm_option(a, lcm_vars) = v;
			i++;
			lcm_opt = a;
		} else if (strcmp(a, "--environments") == 0 && v) {
			char *end;
			errno = 0;
			envs = strtol(v, &end, 10);
			if (*end || errno || envs < 1 ||
			    envs > EVO_REMOTE_SERVE_MAX_ENVS) {
				fprintf(stderr,
					"evo serve: --environments expects a "
					"whole number 1..%d, found '%s'\n",
					EVO_REMOTE_SERVE_MAX_ENVS, v);
				return 2;
			}
			envs_set = 1;
			lcm_opt = a;
			i++;
		} else if (a[0] == '-' || task_path) {
			fprintf(stderr, "evo serve: unexpected argument '%s'\n",
				a);
			evo_serve_usage(stderr);
			return 2;
		} else {
			task_path = a;
		}
	}
	if (!task_path) {
		evo_serve_usage(stderr);
		return 2;
	}
	if (robot_opt && !as_robot) {
		fprintf(stderr, "evo serve: %s is for a robot (--robot)\n",
			robot_opt);
		return 2;
	}
	if (as_robot && envs_set && envs != 1) {
		fprintf(stderr,
			"evo serve: a robot runs one environment; --robot "
			"takes no --environments %ld\n",
			envs);
		return 2;
	}
	if (can_url && lcm_opt) {
		fprintf(
		    stderr,
		    "evo serve: %s is for LCM; over CAN (--can) a robot is "
		    "its bus, with no name, URL or environments of its own\n",
		    lcm_opt);
		return 2;
	}
	if (can_url && tick_ms > 6553.5) {
		fprintf(stderr,
			"evo serve: --tick-ms over CAN is at most 6553.5 (a "
			"BODY frame says the period in 0.1 ms, in 16 bits)\n");
		return 2;
	}
	long tick_us = lround(tick_ms * 1000);
	if (as_robot && tick_us < 1)
		tick_us = 1;
	char own[EVO_REMOTE_NAME_MAX];
	if (!name) {
		snprintf(own, sizeof own, "evo-serve-%ld", (long)getpid());
		name = own;
	}
	if (!evo_wire_name_ok(name)) {
		fprintf(stderr,
			"evo serve: --name '%s': a remote's name is 1..63 "
			"letters, digits, '_' or '-'\n",
			name);
		return 2;
	}
	/* a server's lines go to a log as they happen, not when it ends */
	setvbuf(stdout, NULL, _IOLBF, 0);
	evo_cmd_catch_stop();

	evo_err err = {{0}};
	evo_task task;
	if (evo_task_load(task_path, &task, &err)) {
		fprintf(stderr, "%s\n", err.msg);
		return 1;
	}
	if (can_url) {
		evo_serve_can_def def = {
		    .task = &task,
		    .task_path = task_path,
		    .url = can_url,
		    .tick_ms = tick_ms,
		    .timeout = timeout,
		    .stop = &evo_cmd_stop_requested,
		};
		int crc = evo_serve_can(&def);
		evo_task_free(&task);
		return crc;
	}
	if (!url)
		url = evo_simbatch_get(task.sb, "LCMURL");
	server sv;
	memset(&sv, 0, sizeof sv);
	int rc = 1;
	/* the task's remote keys, for its LCMKEYFILE (and their checks) */
	evo_remote_opts ro;
	if (evo_remote_opts_from_task(
		task.sb, task_path,
		as_robot ? EVO_REMOTE_ROBOT : EVO_REMOTE_SIMULATOR, &ro, &err))
		goto out;
	if (key_file) {
		char why[600];
		if (evo_wire_key_read(key_file, &ro.key, why, sizeof why)) {
			evo_fail(&err, "evo serve: --key-file: %s", why);
			goto out;
		}
	}
	sv.env = calloc((size_t)envs, sizeof *sv.env);
	if (!sv.env) {
		fprintf(stderr, "evo serve: out of memory\n");
		goto out;
	}
	for (long i = 0; i < envs; i++) {
		sv.env[i].sim =
		    evo_sim_create(task.mind, task.sb, task_path, &err);
		if (!sv.env[i].sim) {
			say_which_world(&task, task_path, &err);
			goto out;
		}
	}
	const evo_botdesc *bd = task.mind->botdesc;
	evo_wire_hello *h = &sv.hello;
	h->protocol = EVO_WIRE_PROTOCOL;
	snprintf(h->name, sizeof h->name, "%s", name);
	h->session = new_session();
	h->kind = as_robot ? EVO_REMOTE_ROBOT : EVO_REMOTE_SIMULATOR;
	h->environments = (int32_t)envs;
	h->tick_us = as_robot ? (int32_t)tick_us : 0;
	h->n_sensors = bd->n_sensors;
	h->n_actuators = bd->n_actuators;
	for (unsigned i = 0; i < bd->n_sensors; i++)
		snprintf(h->sensor[i], EVO_NAME_MAX, "%s", bd->sensor[i].name);
	for (unsigned i = 0; i < bd->n_actuators; i++)
		snprintf(h->actuator[i], EVO_NAME_MAX, "%s",
			 bd->actuator[i].name);
	snprintf(sv.ch_control, sizeof sv.ch_control, "EVO_%s_CONTROL", name);
	snprintf(sv.ch_command, sizeof sv.ch_command, "EVO_%s_COMMAND", name);
	snprintf(sv.ch_sensors, sizeof sv.ch_sensors, "EVO_%s_SENSORS", name);
	sv.link = evo_link_open(url, &err);
	if (!sv.link || evo_link_subscribe(sv.link, "EVO_WHO", &err))
		goto out;
	if (ro.key.len)
		evo_link_set_key(sv.link, &ro.key, "evo serve");
	if (!data_url)
		data_url_for(evo_link_url(sv.link), name, h->url,
			     sizeof h->url);
	else if (strcmp(data_url, "same") != 0)
		snprintf(h->url, sizeof h->url, "%s", data_url);
	if (h->url[0] && strcmp(h->url, evo_link_url(sv.link)) != 0) {
		sv.data = evo_link_open(h->url, &err);
		if (!sv.data)
			goto out;
		if (ro.key.len)
			evo_link_set_key(sv.data, &ro.key, "evo serve");
	} else {
		h->url[0] = 0;
		sv.data = sv.link;
	}
	if (evo_link_subscribe(sv.data, sv.ch_control, &err) ||
	    evo_link_subscribe(sv.data, sv.ch_command, &err))
		goto out;
	if (as_robot) {
		printf("evo serve: %s serves %s on %s as a robot (its episodes "
		       "on %s), a tick every %.3f ms, neutral after %.3g s "
		       "without a command\n",
		       name, task_path, evo_link_url(sv.link),
		       evo_link_url(sv.data), tick_us * 1e-3, timeout);
		const char *tl = evo_simbatch_get(task.sb, "TICKLIM");
		if (evo_serve_robot(&sv, tick_us * 1e-6, timeout,
				    tl ? strtoll(tl, NULL, 10) : 0, &err) == 0)
			rc = 0;
	} else {
		printf("evo serve: %s serves %s on %s (%ld environment%s; its "
		       "episodes on %s)\n",
		       name, task_path, evo_link_url(sv.link), envs,
		       envs == 1 ? "" : "s", evo_link_url(sv.data));
		fflush(stdout);
		if (evo_serve_lockstep(&sv, &err) == 0)
			rc = 0;
	}
out:
	if (rc && err.msg[0])
		fprintf(stderr, "%s\n", err.msg);
	evo_report_drops("evo serve", "message", "", sv.dropped, 1,
			 EVO_WIRE_N_REASONS, reason_name);
	if (sv.link)
		evo_link_report(sv.link);
	if (sv.data && sv.data != sv.link) {
		evo_link_report(sv.data);
		evo_link_close(sv.data);
	}
	evo_link_close(sv.link);
	memset(&ro.key, 0, sizeof ro.key);
	for (long i = 0; sv.env && i < envs; i++)
		evo_sim_destroy(sv.env[i].sim);
	free(sv.env);
	evo_task_free(&task);
	return rc;
}
