/* evo — private to the learning loop's driver (sim/learn/learn.c,
 * learn_eval.c, learn_runfolder.c, learn_skills.c): the run's state that
 * the `evo.learn` module's functions share, and the functions each file
 * gives the module's table. No other file may use it. */
#ifndef EVO_LEARN_INTERNAL_H
#define EVO_LEARN_INTERNAL_H

#include <lua.h>
#include <stddef.h>

#include "base/err.h"
#include "learn/evaluate.h"
#include "learn/learn.h"
#include "learn/runlog.h"
#include "lua/lua_evo.h"
#include "mind/task.h"

/* The most skills a LEARNSIMCONTINUOUS hierarchy may train. */
#define CONT_MAX_SKILLS 64

typedef struct learn {
	const char *task_path;
	evo_task *task;
	const evo_learn_opts *opts;
	evo_evaluator *ev;
	evo_runlog log;
	int log_open;
	char run_dir[1024];
	char skill[EVO_NAME_MAX];
	double started;
	int first; /* the generation this process started with */
	int tty;
	int n_extra; /* log columns the loop adds after the metrics */
	char extra[6][EVO_RUNLOG_COLUMN_MAX];
	/* LEARNSIMCONTINUOUS: the skills in the order of their turns (their
	 * indices in task->mind), and the evaluator's definition of the
	 * current turn with the networks the other skills run */
	int continuous;
	int openended; /* TYPE:OPENENDED: lua/learn/openended.lua */
	int n_order;
	int order[CONT_MAX_SKILLS];
	evo_net_choice choice[CONT_MAX_SKILLS];
	char choice_path[CONT_MAX_SKILLS][1200];
	evo_eval_def ed;
	/* OPENENDED's development (evo.grow): the grown mind folder's task,
	 * and the names of the skills whose networks are chosen */
	char grown_task[1200];
	char choice_skill[CONT_MAX_SKILLS][EVO_NAME_MAX];
	evo_lua_mem *mem; /* the loop's state's memory (LUAMEMORY) */
	/* evo.evaluate's networks, kept from batch to batch (a batch of
	 * 150 is 8 MB: allocated and cleared anew, it cost more than
	 * evaluating XOR's networks) */
	evo_netdesc *descs;
	int n_descs;
	int n_behaviour; /* the size of every behaviour so far; -1 before */
	/* evo.save's last folder (best/), checked for links and made: a
	 * generation's file then costs its write and rename only */
	char saved_folder[256];
} learn;

/* the driver (learn.c) */
learn *learn_ctx(lua_State *L);
int learn_raise_msg(lua_State *L, const char *msg);
double learn_now(void);

/* batches (learn_eval.c) */
double learn_field_num(lua_State *L, int idx, const char *key, double dflt);
lua_Integer learn_field_int(lua_State *L, int idx, const char *key,
			     lua_Integer lo, lua_Integer hi, int which);
int learn_l_descriptors(lua_State *L);
int learn_l_evaluate(lua_State *L);
int learn_l_set_team_net(lua_State *L);
int learn_l_set_genome(lua_State *L);
int learn_l_success_test(lua_State *L);

/* the run folder (learn_runfolder.c) */
int learn_l_open_log(lua_State *L);
int learn_l_log(lua_State *L);
int learn_l_save(lua_State *L);
int learn_l_read(lua_State *L);
int learn_keep_replaced(const learn *l, const char *path, const char *text,
			 size_t len, const char *name, char *kept, size_t cap,
			 evo_err *err);
int learn_l_save_champion(lua_State *L);
int learn_l_curve(lua_State *L);
int learn_l_heatmap(lua_State *L);
int learn_l_gallery(lua_State *L);
int learn_l_clock(lua_State *L);
int learn_l_save_many(lua_State *L);
int learn_l_print(lua_State *L);

/* skills' turns and development (learn_skills.c) */
int learn_l_begin_turn(lua_State *L);
int learn_l_grow(lua_State *L);
int learn_l_read_skill_net(lua_State *L);
int learn_l_save_skill_net(lua_State *L);
int learn_continuous_order(const char *task_path, const evo_task *t,
			    int *order, int *n, evo_err *err);

#endif
