/* A robot over LCM or CAN behind one interface (sim/remote/robot.h). */
#define _POSIX_C_SOURCE 200809L
#include "remote/robot.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "remote/can.h"
#include "remote/can_robot.h"
#include "remote/session.h"

struct evo_robot_conn {
	/* over LCM */
	evo_remotes *lcm;
	evo_robot rb;
	double timeout;
	/* over CAN */
	evo_can_robot *can;
	char about[512];
};

int evo_robot_task_check(const evo_simbatch *task, const char *type,
			 const char *task_path, evo_err *err)
{
	const char *url = evo_simbatch_get(task, "CANURL");
	if (!url) {
		if (!strstr(type, "REMOTE"))
			return 0;
		/* over LCM: evo check refuses what evo run would (its URL,
		 * names and key file, and a task that names no remote and
		 * has no key) */
		evo_remote_opts o;
		if (evo_remote_opts_from_task(task, task_path,
					      strcmp(type, "DEMOREMOTE") == 0
						  ? EVO_REMOTE_ROBOT
						  : EVO_REMOTE_SIMULATOR,
					      &o, err))
			return -1;
		/* a DEMOREMOTE task may reach its robot over CAN by evo run
		 * --can, with neither: evo_remotes_open asks for them when it
		 * goes over LCM */
		if (strcmp(type, "DEMOREMOTE") != 0 &&
		    evo_remote_opts_chosen(&o, err))
			return -1;
		return 0;
	}
	if (strcmp(type, "DEMOREMOTE") != 0)
		return evo_fail(
		    err,
		    "%s: CANURL is for DEMOREMOTE tasks (a robot on "
		    "a CAN bus); a %s task's remote is reached over "
		    "LCM",
		    task_path, type);
	evo_err inner;
	if (evo_can_url_check(url, &inner))
		return evo_fail(err, "%s: CANURL: %s", task_path, inner.msg);
	return 0;
}

evo_robot_conn *evo_robot_conn_open(const evo_robot_conn_def *def, evo_err *err)
{
	evo_remote_opts ro;
	if (evo_remote_opts_from_task(def->task, def->task_path,
				      EVO_REMOTE_ROBOT, &ro, err))
		return NULL;
	ro.stop = def->stop;
	evo_robot_conn *c = calloc(1, sizeof *c);
	if (!c) {
		evo_fail(err, "out of memory");
		return NULL;
	}
	c->timeout = ro.timeout;
	const char *url = def->can_url;
	if (!url)
		url = evo_simbatch_get(def->task, "CANURL");
	if (url) {
		evo_can_robot_def cd = {
		    .url = url,
		    .mind = def->mind,
		    .timeout = ro.timeout,
		    .stop = def->stop,
		};
		c->can = evo_can_robot_open(&cd, err);
		if (!c->can) {
			free(c);
			return NULL;
		}
		snprintf(c->about, sizeof c->about, "%s",
			 evo_can_robot_about(c->can));
		return c;
	}
	c->lcm = evo_remote_connect(def->mind, &ro, err);
	if (!c->lcm) {
		free(c);
		return NULL;
	}
	const evo_wire_hello *h = &c->lcm->r[0]->hello;
	snprintf(c->about, sizeof c->about,
		 "remote %s: robot, a tick every %.3f ms", h->name,
		 h->tick_us * 1e-3);
	return c;
}

void evo_robot_conn_close(evo_robot_conn *c)
{
	if (!c)
		return;
	evo_can_robot_close(c->can);
	evo_remotes_close(c->lcm);
	free(c);
}

const char *evo_robot_conn_about(const evo_robot_conn *c)
{
	return c->about;
}

const char *evo_robot_conn_name(const evo_robot_conn *c)
{
	return c->can ? evo_can_robot_name(c->can) : c->lcm->r[0]->hello.name;
}

double evo_robot_conn_period(const evo_robot_conn *c)
{
	return c->can ? evo_can_robot_period(c->can)
		      : c->lcm->r[0]->hello.tick_us * 1e-6;
}

double evo_robot_conn_timeout(const evo_robot_conn *c)
{
	return c->timeout;
}

int evo_robot_conn_start(evo_robot_conn *c, int64_t episode,
			 uint64_t layout_seed, uint64_t seed, evo_err *err)
{
	if (c->can)
		return evo_can_robot_start(c->can, episode, layout_seed, seed,
					   err);
	return evo_robot_start(c->lcm, &c->rb, episode, layout_seed, seed, err);
}

int evo_robot_conn_next(evo_robot_conn *c, int timeout_ms, evo_err *err)
{
	return c->can ? evo_can_robot_next(c->can, timeout_ms, err)
		      : evo_robot_next(&c->rb, timeout_ms, err);
}

int evo_robot_conn_answer(evo_robot_conn *c, const evo_q16 *commands,
			  evo_err *err)
{
	if (c->can)
		return evo_can_robot_answer(c->can, commands, err);
	double out[EVO_MAX_ACTUATORS];
	unsigned n = c->lcm->mind->botdesc->n_actuators;
	for (unsigned i = 0; i < n; i++)
		out[i] = evo_q16_to_double(commands[i]);
	return evo_robot_answer(&c->rb, out, err);
}

void evo_robot_conn_sensors(const evo_robot_conn *c, evo_q16 *values)
{
	if (c->can) {
		evo_can_robot_sensors(c->can, values);
		return;
	}
	double in[EVO_MAX_SENSORS];
	unsigned n = c->lcm->mind->botdesc->n_sensors;
	evo_remote_sensors(c->lcm->r[0], 0, in);
	for (unsigned i = 0; i < n; i++)
		values[i] = evo_q16_from_sensor(in[i]);
}

void evo_robot_conn_status(const evo_robot_conn *c, evo_robot_status *s)
{
	if (c->can) {
		evo_can_robot_status(c->can, s);
		return;
	}
	const evo_robot *rb = &c->rb;
	s->tick = rb->set ? rb->tick : -1;
	s->done = rb->done;
	s->reward = rb->reward;
	s->in_time = rb->in_time;
	s->late = rb->late;
	s->unanswered = rb->unanswered;
	s->missing = rb->missing;
	s->quiet = rb->set ? evo_robot_quiet(rb) : 0;
}

void evo_robot_conn_report(const evo_robot_conn *c)
{
	if (c->can)
		evo_can_robot_report(c->can);
	else if (c->rb.set)
		evo_robot_report(&c->rb);
}
