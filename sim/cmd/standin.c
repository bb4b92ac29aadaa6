/* A world standing in for a robot, over LCM or CAN (cmd/standin.h): the
 * schedule of its periods, its episodes, the commands in force and the
 * counts `evo serve --robot` and `evo serve --can` report. */
#define _POSIX_C_SOURCE 200809L
#include "cmd/standin.h"

#include <stdio.h>
#include <string.h>
#include <time.h>

#include "base/clock.h"

static int stopping(const evo_standin *s)
{
	return s->stop && *s->stop;
}

void evo_standin_neutral(evo_standin *s)
{
	for (unsigned j = 0; j < s->na; j++)
		s->cmd[j] = 0.5;
}

/* The world steps once with the commands in force. */
static int step(evo_standin *s, evo_err *err)
{
	int done = evo_sim_act(s->sim, s->cmd, err);
	if (done < 0)
		return -1;
	s->stepped = 1;
	s->ended = done;
	return 0;
}

int evo_standin_reset(evo_standin *s, int64_t e, uint64_t layout_seed,
		      uint64_t seed, evo_err *err)
{
	double t = evo_clock_now();
	if (s->active && e == s->episode && !s->commanded &&
	    t - s->started_at < 1.0)
		return 1;
	if (evo_sim_reset(s->sim, (int)e, layout_seed, seed, err))
		return -1;
	s->active = 1;
	s->restart = 1;
	s->episode = e;
	s->tick = 0;
	s->started_at = s->commanded_at = t;
	s->commanded = 0;
	s->neutral = 0;
	evo_standin_neutral(s);
	printf("evo serve: robot %s: episode %lld starts\n", s->name,
	       (long long)e);
	fflush(stdout);
	return 0;
}

/* The episode is over: every actuator neutral until a RESET, said as
 * "evo serve: robot NAME: <how> episode E <at> tick T: ...". */
static void halt(evo_standin *s, const char *how, const char *at)
{
	s->active = 0;
	evo_standin_neutral(s);
	printf("evo serve: robot %s: %sepisode %lld %s tick %lld: every "
	       "actuator neutral; waiting for a RESET\n",
	       s->name, how, (long long)s->episode, at, (long long)s->tick);
	fflush(stdout);
}

void evo_standin_stop(evo_standin *s)
{
	s->restart = 1;
	halt(s, "evo stopped ", "at");
}

void evo_standin_late(evo_standin *s, int64_t tick)
{
	if (s->late++ == 0)
		printf("evo serve: robot %s: the command of tick %lld came "
		       "during tick %lld, after its period; later ones are "
		       "counted\n",
		       s->name, (long long)tick, (long long)s->tick);
}

int evo_standin_command(evo_standin *s, const double *cmd, evo_err *err)
{
	double t = evo_clock_now();
	if (s->neutral)
		printf("evo serve: robot %s: commands again at tick %lld, "
		       "after %.2f s\n",
		       s->name, (long long)s->tick, t - s->commanded_at);
	s->neutral = 0;
	s->commanded = 1;
	s->commanded_at = t;
	s->in_time++;
	memcpy(s->cmd, cmd, s->na * sizeof *cmd);
	return step(s, err);
}

/* No command of this tick within its period: the commands before hold,
 * or every actuator goes neutral once none has come for the timeout. */
static int no_command(evo_standin *s, evo_err *err)
{
	double quiet = evo_clock_now() - s->commanded_at;
	if (quiet >= s->timeout) {
		if (!s->neutral) {
			printf("evo serve: robot %s: no command for %.2f s, "
			       "at tick %lld: every actuator neutral\n",
			       s->name, quiet, (long long)s->tick);
			fflush(stdout);
			evo_standin_neutral(s);
			s->neutral = 1;
		}
		s->neutral_ticks++;
	} else if (s->held++ == 0) {
		printf("evo serve: robot %s: no command for tick %lld within "
		       "its period: the commands before hold; later ones are "
		       "counted\n",
		       s->name, (long long)s->tick);
	}
	return step(s, err);
}

/* One period: the sensors out at its start, its command awaited until
 * its end (the world steps as soon as it comes), the world stepped with
 * the commands in force if it did not. */
static int one_tick(evo_standin *s, double start, evo_err *err)
{
	if (s->io.send_tick(s->io.ctx, err))
		return -1;
	s->stepped = s->ended = s->restart = 0;
	double deadline = start + s->period;
	for (;;) {
		if (stopping(s) || s->restart)
			return 0;
		double left = deadline - evo_clock_now();
		if (left <= 0)
			break;
		int ms = (int)(left * 1e3) + 1;
		if (s->io.message(s->io.ctx, ms < 100 ? ms : 100, err))
			return -1;
	}
	if (!s->stepped && no_command(s, err))
		return -1;
	s->ticks++;
	s->tick++;
	/* a simulated episode lasts TICKLIM ticks, as DEMOSIM's: the
	 * scene's timeout control ends it one check later */
	if (s->limit > 0 && s->tick >= s->limit)
		s->ended = 1;
	if (s->ended) {
		/* the world ended the episode: its last sensors say so */
		if (s->io.send_end(s->io.ctx, err))
			return -1;
		halt(s, "", "ended at");
	}
	return 0;
}

int evo_standin_run(evo_standin *s, evo_err *err)
{
	if (s->io.announce(s->io.ctx, err))
		return -1;
	double next = 0;
	while (!stopping(s)) {
		if (!s->active) {
			s->restart = 0;
			if (s->io.message(s->io.ctx, 100, err))
				return -1;
			next = evo_clock_now();
			continue;
		}
		/* a period that starts late (the last one overran) starts
		 * now, and the schedule goes on from there */
		double t = evo_clock_now();
		if (t > next + s->period) {
			if (s->tick > 0)
				s->overruns++;
			next = t;
		}
		double start = next;
		if (one_tick(s, start, err))
			return -1;
		next = s->restart ? evo_clock_now() : start + s->period;
	}
	return 0;
}

void evo_standin_report(const evo_standin *s)
{
	printf("evo serve: robot %s: %lu ticks: %lu commanded in time, %lu "
	       "held the commands before, %lu neutral; %lu commands came "
	       "late; %lu periods overran\n",
	       s->name, s->ticks, s->in_time, s->held, s->neutral_ticks,
	       s->late, s->overruns);
}
