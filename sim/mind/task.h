/* A task: a parsed .simbatch and the mind folder it runs.
 *
 * The mind folder is the folder that holds the Tasks/ folder the .simbatch
 * sits in (Minds/Agent/Tasks/T.simbatch runs Minds/Agent), so a task runs
 * from any working directory, Tasks/ itself included. A .simbatch outside a Tasks/ folder names its
 * mind with ROOTFOLDER, relative to the working directory, as EvoAgents
 * did. docs/formats.md, .simbatch. */
#ifndef EVO_TASK_H
#define EVO_TASK_H

#include "base/err.h"
#include "evo/evo.h"
#include "mind/mindfolder.h"

/* Teams (docs/teams.md): a DEMO2DSIMMULTI or LEARN2DSIMMULTI task lists
 * them, one TEAM:NAME:MIND:BOTMODEL:SIZE:MASTERSKILL[:LEARNINGSKILL] line
 * each. */
#define EVO_MAX_TEAMS	  12
#define EVO_TEAM_MAX_SIZE 4096
#define EVO_TEAM_NAME_MAX 32 /* with its NUL */

typedef struct evo_team {
	char name[EVO_TEAM_NAME_MAX];
	char botmodel[EVO_NAME_MAX];
	char master[EVO_NAME_MAX];
	char learning_skill[EVO_NAME_MAX]; /* the 6th field, else
					    * LEARNINGSKILL; "" when none */
	int size;			   /* bots, 1..EVO_TEAM_MAX_SIZE */
	uint32_t line;			   /* its TEAM line in the task file */
	int learns;	      /* a team of LEARNINGTEAM (LEARN2DSIMMULTI) */
	evo_mindfolder *mind; /* its own mind folder, loaded */
	/* Members with networks of their own (a heterogeneous team's
	 * Skills/S/S.K.net for member K, docs/teams.md): member[k] is member
	 * k + 1's mind, NULL for one that runs the team's; member is NULL
	 * when none has any (and for a team that learns). */
	evo_mindfolder **member;
} evo_team;

typedef struct evo_task {
	evo_simbatch *sb;
	const char *type; /* TYPE, upper-cased (an entry of evo_task_types) */
	/* The mind folder: a one-agent task's; in a team task the first
	 * learning team's (LEARN2DSIMMULTI), else the first team's, owned
	 * by that team. */
	evo_mindfolder *mind;
	uint64_t seed; /* the run's: evo_task_opts' seed, else SEED, else 1 */
	/* Teams: none (n_teams 0) in a one-agent task. */
	int n_teams;
	evo_team *team;
	int n_learning;		     /* LEARNINGTEAM's teams, in order */
	int learning[EVO_MAX_TEAMS]; /* their indices in team[] */
	int heterogeneous;	     /* TEAMGENOME:HETEROGENEOUS */
	int own_fitness;	     /* TEAMFITNESS:OWN */
	int alternate;		     /* ALTERNATE: generations per turn */
} evo_task;

/* 1 for the task types of teams, DEMO2DSIMMULTI and LEARN2DSIMMULTI. */
int evo_task_type_has_teams(const char *type);

/* What a command line changes in a task (`evo run`'s options). */
typedef struct evo_task_opts {
	int seed_set; /* --seed given: seed replaces the task's SEED */
	uint64_t seed;
	/* --net SKILL=SOURCE: networks run instead of the skills' own
	 * (mind/mindfolder.h, evo_net_choice) */
	const evo_net_choice *nets;
	unsigned n_nets;
	/* evo check: neural skills not trained yet load with zero weights
	 * (evo_mindfolder_opts.untrained_ok) */
	int untrained_ok;
} evo_task_opts;

/* Parse path, check the keys its TYPE needs, load its mind folder.
 * Warnings (unknown keys) go to stderr. Returns 0, or -1 with err set. */
int evo_task_load(const char *path, evo_task *t, evo_err *err);

/* The same, with a command line's changes (o may be NULL). */
int evo_task_load_opts(const char *path, const evo_task_opts *o, evo_task *t,
		       evo_err *err);

void evo_task_free(evo_task *t);

#endif
