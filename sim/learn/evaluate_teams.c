/* The evaluator's team tasks (sim/learn/evaluate.h, LEARN2DSIMMULTI,
 * docs/teams.md): each worker's teams loaded, the teams' networks set
 * and applied, one evaluation of a team, and a batch of a team's
 * candidates in groups. */
#define _POSIX_C_SOURCE 200809L

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "base/fileio.h"
#include "learn/evaluate_internal.h"
#include "learn/literature.h"
#include "mind/task.h"
#include "tasksim/tasksim.h"
#include "world2d/scene.h"

/* Before a team batch: every team but the one that learns runs its
 * network of evo_evaluator_set_team_net, or its own as loaded (a team
 * that learned in an earlier batch still holds a candidate), whenever
 * those changed or another team learns than in w's last batch. */
int eval_apply_team_nets(worker *w, evo_err *err)
{
	evo_evaluator *ev = w->ev;
	if (w->nets_seen == ev->nets_version && w->last_team == ev->team)
		return 0;
	for (int t = 0; t < ev->n_teams; t++) {
		if (t == ev->team || w->team_skill[t] < 0)
			continue;
		const evo_netdesc *net =
		    ev->team_net[t] ? ev->team_net[t] : w->own_net[t];
		evo_mindfolder *m = w->task.team[t].mind;
		*m->net[w->team_skill[t]] = *net;
		if (evo_mindfolder_rebuild(m, err) ||
		    evo_sim_set_team_mind(w->sim, t, m, err))
			return -1;
	}
	w->nets_seen = ev->nets_version;
	w->last_team = ev->team;
	return 0;
}

/* Evaluation j of a team batch on worker w: the learning team's members
 * run their candidates, the repetitions run, and what the team and each
 * member earned is kept in unit[j] and own[j * size ..]. */
int eval_evaluate_team_unit(worker *w, int j, evo_err *err)
{
	evo_evaluator *ev = w->ev;
	int t = ev->team;
	const evo_sim_team *st = &w->sim->team[t];
	int size = st->size;
	const int *g = ev->groups + (size_t)j * size;
	int k = w->team_skill[t];
	if (!ev->heterogeneous) {
		evo_mindfolder *m = w->task.team[t].mind;
		*m->net[k] = *ev->cand[g[0]];
		if (evo_mindfolder_rebuild(m, err) ||
		    evo_sim_set_team_mind(w->sim, t, m, err))
			return -1;
	} else {
		for (int i = 0; i < size; i++) {
			evo_mindfolder *m = w->member[t][i];
			*m->net[k] = *ev->cand[g[i]];
			if (evo_mindfolder_rebuild(m, err) ||
			    evo_sim_set_agent_mind(w->sim, st->first + i, m,
						   err))
				return -1;
		}
	}
	unit_result *u = &ev->unit[j];
	double *own = ev->own + (size_t)j * size;
	memset(u, 0, sizeof *u);
	for (int i = 0; i < size; i++)
		own[i] = 0;
	for (int r = 0; r < ev->reps; r++) {
		if (eval_run_episode(w->sim, ev->seed, ev->gen, j, r, ev->ticks,
				     err))
			return -1;
		u->team_fitness += evo_sim_team_reward(w->sim, t);
		u->wins += evo_sim_winner(w->sim) == t;
		for (int i = 0; i < size; i++) {
			int b = w->sim->agent[st->first + i].bot;
			own[i] += evo_sim_bot_reward(w->sim, b);
			u->collisions += evo_sim_collisions(w->sim, st->first + i);
		}
		for (int m = 0; m < ev->n_metrics; m++)
			u->metric[m] += evo_sim_metric(w->sim, m);
	}
	for (int m = 0; m < ev->n_metrics; m++)
		u->metric[m] /= ev->reps;
	return 0;
}

/* A team task's worker: every team's learning skill, a mind of its own
 * for each member of a heterogeneous learning team, and the scene of
 * every team. */
int eval_load_teams(evo_evaluator *ev, worker *w, evo_err *err)
{
	evo_task *t = &w->task;
	for (int k = 0; k < t->n_teams; k++) {
		const evo_team *tm = &t->team[k];
		w->team_skill[k] =
		    tm->learning_skill[0]
			? evo_mindfolder_skill(tm->mind, tm->learning_skill)
			: -1;
		if (w->team_skill[k] >= 0 && !tm->mind->net[w->team_skill[k]])
			w->team_skill[k] = -1;
		if (w->team_skill[k] >= 0) {
			w->own_net[k] = malloc(sizeof *w->own_net[k]);
			if (!w->own_net[k])
				return evo_fail(err, "out of memory");
			*w->own_net[k] = *tm->mind->net[w->team_skill[k]];
		}
		if (!tm->learns || !t->heterogeneous)
			continue;
		w->member[k] = calloc((size_t)tm->size, sizeof *w->member[k]);
		if (!w->member[k])
			return evo_fail(err, "out of memory");
		evo_mindfolder_opts opts = {
		    .master = tm->master,
		    .learning_skill = tm->learning_skill,
		    .seed = t->seed,
		};
		for (int i = 0; i < tm->size; i++)
			if (!(w->member[k][i] = evo_mindfolder_load(
				  tm->mind->root, &opts, err)))
				return -1;
	}
	(void)ev;
	w->last_team = -1;
	w->skill = w->team_skill[t->learning[0]];
	w->sim = evo_sim_create_task(t, ev->task_path, err);
	return w->sim ? 0 : -1;
}

/* ---- team tasks -----------------------------------------------------------
 */

int evo_evaluator_n_teams(const evo_evaluator *ev)
{
	return ev->remote ? 0 : ev->n_teams;
}

int evo_evaluator_team_size(const evo_evaluator *ev, int team)
{
	return team >= 0 && team < evo_evaluator_n_teams(ev)
		   ? ev->w[0].task.team[team].size
		   : 0;
}

static const evo_ades *team_skill(const evo_evaluator *ev, int team)
{
	if (team < 0 || team >= evo_evaluator_n_teams(ev) ||
	    ev->w[0].team_skill[team] < 0)
		return NULL;
	return &ev->w[0].task.team[team].mind->skill[ev->w[0].team_skill[team]];
}

unsigned evo_evaluator_team_n_in(const evo_evaluator *ev, int team)
{
	const evo_ades *a = team_skill(ev, team);
	return a ? a->n_in : 0;
}

unsigned evo_evaluator_team_n_out(const evo_evaluator *ev, int team)
{
	const evo_ades *a = team_skill(ev, team);
	return a ? a->n_out : 0;
}

int evo_evaluator_set_team_net(evo_evaluator *ev, int team,
			       const evo_netdesc *net, evo_err *err)
{
	const evo_ades *a = team_skill(ev, team);
	if (!a)
		return evo_fail(err, "team %d has no learning skill to set",
				team);
	if (net->n_in != a->n_in || net->n_out != a->n_out)
		return evo_fail(err,
				"team %s: a network of %u inputs and %u "
				"outputs for skill %s of %u and %u",
				ev->w[0].task.team[team].name,
				(unsigned)net->n_in, (unsigned)net->n_out,
				a->name, (unsigned)a->n_in, (unsigned)a->n_out);
	if (!ev->team_net[team] &&
	    !(ev->team_net[team] = malloc(sizeof *ev->team_net[team])))
		return evo_fail(err, "out of memory");
	/* workers are idle between batches: no lock is needed for the
	 * net, and the version is read under the batch's lock */
	*ev->team_net[team] = *net;
	pthread_mutex_lock(&ev->mu);
	ev->nets_version++;
	pthread_mutex_unlock(&ev->mu);
	return 0;
}

int evo_evaluate_teams(evo_evaluator *ev, int team,
		       const evo_netdesc *const *candidates, int n,
		       const int *groups, int n_groups, int gen,
		       evo_eval_result *res, evo_err *err)
{
	const evo_ades *a = team_skill(ev, team);
	if (!a || !ev->w[0].task.team[team].learns)
		return evo_fail(err, "team %d is not a learning team", team);
	int size = ev->w[0].task.team[team].size;
	if (n < 1 || n_groups < 1 || !candidates || !groups || !res)
		return evo_fail(err, "evaluate: no candidates or no teams");
	for (int i = 0; i < n; i++) {
		const evo_netdesc *c = candidates[i];
		if (!c)
			return evo_fail(err, "candidate %d: no network", i);
		if (c->n_in != a->n_in || c->n_out != a->n_out)
			return evo_fail(err,
					"candidate %d: the network has %u "
					"inputs and %u outputs; skill %s has "
					"%u inputs and %u outputs",
					i, (unsigned)c->n_in,
					(unsigned)c->n_out, a->name,
					(unsigned)a->n_in, (unsigned)a->n_out);
	}
	/* each candidate's first evaluation and member, in order */
	int *first = malloc((size_t)n * sizeof *first);
	unit_result *unit = calloc((size_t)n_groups, sizeof *unit);
	double *own = calloc((size_t)n_groups * size, sizeof *own);
	if (!first || !unit || !own) {
		free(first);
		free(unit);
		free(own);
		return evo_fail(err, "out of memory");
	}
	for (int i = 0; i < n; i++)
		first[i] = -1;
	for (long k = 0; k < (long)n_groups * size; k++) {
		int c = groups[k];
		if (c < 0 || c >= n) {
			free(first);
			free(unit);
			free(own);
			return evo_fail(err,
					"team %ld, member %ld: no candidate %d",
					k / size, k % size, c);
		}
		if (first[c] < 0)
			first[c] = (int)(k / size);
	}
	for (int i = 0; i < n; i++)
		if (first[i] < 0) {
			free(first);
			free(unit);
			free(own);
			return evo_fail(err, "candidate %d is in no team", i);
		}
	eval_begin_batch(ev, candidates, n_groups, gen);
	ev->res = NULL;
	ev->team = team;
	ev->groups = groups;
	ev->unit = unit;
	ev->own = own;
	int failed = eval_run_batch(ev, err);
	pthread_mutex_unlock(&ev->mu);
	/* Each candidate's result from its first evaluation, worked out
	 * here, in order: nothing depends on which worker ran what. */
	for (int i = 0; i < n && !failed; i++) {
		int j = first[i];
		const unit_result *u = &unit[j];
		evo_eval_result *r = &res[i];
		memset(r, 0, sizeof *r);
		r->group = j;
		r->team_fitness = u->team_fitness;
		r->wins = u->wins;
		r->collisions = u->collisions;
		memcpy(r->metric, u->metric, sizeof r->metric);
		if (!ev->own_fitness) {
			r->fitness = u->team_fitness;
		} else {
			double sum = 0;
			int members = 0;
			for (int m = 0; m < size; m++)
				if (groups[(size_t)j * size + m] == i) {
					sum += own[(size_t)j * size + m];
					members++;
				}
			r->fitness = sum / members;
		}
	}
	free(first);
	free(unit);
	free(own);
	return failed ? -1 : 0;
}
