/* evo — private to sim/lua/: what the files of the scene scripts' `evo`
 * module share (lua_evo.c sets up a state, lua_sandbox.c loads scripts
 * and holds what they may use, lua_args.c reads options and handles,
 * lua_scene.c, lua_scoring.c, lua_bot.c and lua_element.c are the methods
 * of the scene, its rewards, controls and metrics, bots and elements, in
 * either world, and reach the scene through the table of its dimension,
 * lua_dim2d.c or lua_dim3d.c; lua_hooks.c calls Lua from the tick).
 * No other folder may include it. */
#ifndef EVO_LUA_INTERNAL_H
#define EVO_LUA_INTERNAL_H

#include <lauxlib.h>
#include <lua.h>
#include <math.h>

#include "base/rng.h"
#include "lua/lua_evo.h"

typedef struct evo_lua_dim evo_lua_dim;

/* The fields a scene of either dimension has, by address: what the
 * methods read and write without asking the dimension. */
typedef struct evo_lua_view {
	long *tick;
	evo_rng *rng; /* the episode's */
	int *n_bots, *n_elements, *n_rewards, *n_metrics;
	evo_reward **reward;
	evo_metric *metric;
	evo_swarm *swarm;
	evo_err *err;
	double *episode_reward;
	int *winner;
	uint64_t *grid_seed;
} evo_lua_view;

struct evo_lua {
	lua_State *L;
	evo_scene *sc;	    /* a 2D scene's scripts: this one, */
	evo_scene3d *sc3;   /* a 3D scene's: this one (the other NULL) */
	const evo_lua_dim *dim; /* the scene's dimension's functions */
	evo_lua_view v;		/* its fields both dimensions have */
	evo_rng layout_rng; /* scene:layout_random, from the grid seed */
	char mind_dir[1024];
	char lua_dir[1024];
	char botmodel[EVO_NAME_MAX];
	const evo_simbatch *task;
	int n_teams;
	struct {
		char name[32];
		char botmodel[EVO_NAME_MAX];
		char
		    mind_dir[1024]; /* its bot model is looked for here first */
		int size;
		int made; /* bots of the team so far */
	} team[EVO_SCENE_MAX_TEAMS];
	int env_ref; /* the environment's table */
	int episode; /* the episode being reset (env.obstacles) */
	int in_reset; /* env.reset is running: no new elements */
	int ready;    /* env.init has returned: no new metrics */
	int has_post_step;
	/* an OPENENDED run's environment genome for the episodes to come
	 * (scene:genome(), docs/openended.md); not owned, NULL: none */
	const char *genome;
	char env_path[1200];
	char bot_path[1200];
	/* the limits of every call into Lua (evo_lua_pcall): the
	 * instruction budget and time limit of the call under way, what was
	 * used, when it started, and, once a limit is reached, `over` and
	 * its message, which stay: every later hook and call fails with it,
	 * however the script catches the error */
	evo_lua_limits limits;
	evo_lua_mem *mem;
	long budget;
	long used;
	double started, cpu_started, time_limit;
	int in_call;
	int over;
	const char *call_what;
	char over_msg[1400];
	struct evo_lua_watch *watch;
};

/* ---- lua_limits.c: the watchdog beside the count hook ----------------- */

/* A state's entry in the watchdog's list: while a call runs, its
 * deadline, what it is, and the script's file:line last seen (by the
 * count hook, and by the string functions that match patterns). */
struct evo_lua_watch *evo_lua_watch_add(void);
void evo_lua_watch_remove(struct evo_lua_watch *w);
/* A call begins (deadline: limit + grace seconds of the calling thread's
 * CPU time) or ends (limit < 0). Returns the thread's CPU time at the
 * start (evo_lua_cpu_now). */
double evo_lua_watch_call(struct evo_lua_watch *w, const char *what,
			  double limit);
/* The calling thread's CPU time, in seconds. */
double evo_lua_cpu_now(void);
/* The script's file:line now; "" when none. */
void evo_lua_watch_where(struct evo_lua_watch *w, const char *where);
void evo_lua_watch_get_where(struct evo_lua_watch *w, char *out, size_t cap);
/* The signal that stops the run, or 0. */
int evo_lua_stop_signal(void);
double evo_lua_now(void);

/* Instruction budgets of a call into Lua from C (docs/lua.md,
 * "Limits"): loading a script and init run once and may build
 * large scenes; reset runs once an episode; post_step and Lua reward and
 * control functions run every tick. An endless loop in any of them ends
 * the run within about a second. */
#define EVO_LUA_BUDGET_INIT  100000000L
#define EVO_LUA_BUDGET_RESET 10000000L
#define EVO_LUA_BUDGET_TICK  1000000L

/* Time limits of the same calls, in seconds: a C library call (a string
 * pattern that backtracks, a sort) can take seconds in one instruction,
 * which no instruction count sees. A call that ends past its limit fails;
 * one that does not end is stopped by the watchdog EVO_LUA_GRACE seconds
 * after its limit, which ends the process (docs/lua.md). The time is the
 * thread's own (its CPU time; a script cannot wait on anything): on a
 * busy machine, time the thread was not given is not the script's. */
#define EVO_LUA_TIME_INIT  10.0
#define EVO_LUA_TIME_RESET 2.0
#define EVO_LUA_TIME_TICK  0.5
#define EVO_LUA_GRACE	   1.0

/* Registry keys, by their addresses: the evo_lua of a state, and the one
 * scene object that hooks pass to Lua functions. */
extern const char evo_lua_ctx_key;
extern const char evo_lua_scene_key;

/* Metatables of the handles Lua holds. */
#define EVO_LUA_BOT_MT "evo.bot"
#define EVO_LUA_ELEMENT_MT "evo.element"
#define EVO_LUA_SCENE_MT "evo.scene"
#define EVO_LUA_METRIC_MT "evo.metric"

/* The most bots one team has (task.h's EVO_TEAM_MAX_SIZE): a team's
 * reward or control is one per bot. */
#define EVO_TEAM_BOTS_MAX 4096

/* Angles are degrees in Lua, radians in C. */
#define EVO_LUA_DEG (M_PI / 180.0)

/* The evo_lua of a state. */
evo_lua *evo_lua_ctx(lua_State *L);

/* ---- lua_args.c: option tables and handles (each raises a Lua error
 * naming `what` on a bad value) ----------------------------------------- */

/* The name of list closest to word, ignoring case, when it is near
 * enough to be the one meant (a third of word's letters off at most);
 * else NULL. For "did you mean". */
const char *evo_lua_near(const char *word, const char *const *list,
			 size_t n);

/* Raise an error for any key of the table at idx not in `known` (NULL
 * ended), naming the known ones. */
void evo_lua_check_keys(lua_State *L, int idx, const char *what,
			const char *const *known);
double evo_lua_opt_num(lua_State *L, int idx, const char *key, double dflt,
		       const char *what);
/* Options read into doubles: each key of the table at idx, in units of
 * unit (0: 1; EVO_LUA_DEG: degrees into radians), into *v, which holds
 * its default. A list ends with a NULL key. */
typedef struct evo_lua_num {
	const char *key;
	double *v;
	double unit;
} evo_lua_num;
void evo_lua_opt_nums(lua_State *L, int idx, const char *what,
		      const evo_lua_num *nums);
/* evo_lua_opt_nums of the entries given, {key, &v, unit} each. */
#define EVO_LUA_NUMS(L, idx, what, ...)                                       \
	evo_lua_opt_nums(L, idx, what,                                        \
			 (const evo_lua_num[]){__VA_ARGS__, {NULL, NULL, 0}})
const char *evo_lua_opt_str(lua_State *L, int idx, const char *key,
			    const char *dflt, const char *what);
/* Push a handle: a userdata holding index, with metatable mt. */
void evo_lua_push_handle(lua_State *L, const char *mt, int index);
/* The index a bot or element handle at idx holds; raises on a stale one. */
int evo_lua_check_bot(lua_State *L, int idx);
int evo_lua_check_element(lua_State *L, int idx);
int evo_lua_check_metric(lua_State *L, int idx);
/* A target option: an element handle, "nearest_object", or nil
 * (EVO_TARGET_NONE). */
int evo_lua_opt_target(lua_State *L, int idx, const char *key,
		       const char *what);
/* The `bot` option: a bot handle, or the first bot when absent. */
int evo_lua_opt_bot(lua_State *L, int idx, const char *what);
/* The `team` option: a team's name; its index, or -1 when absent. */
int evo_lua_opt_team(lua_State *L, int idx, const char *what);
/* A team's index by name; raises naming the teams when there is none. */
int evo_lua_check_team(lua_State *L, const char *name, const char *what);
/* scene:bot's team option at idx (docs/teams.md; the 3D scene's): the
 * team's index, its model in *model and its next member's name
 * ("Red3") in name; or -1, the model option or the task's BOTMODEL and
 * "bot<n_bots + 1>". Raises on a model given to a team's bot, a team
 * with its SIZE bots, or no model at all. */
int evo_lua_bot_team(lua_State *L, int idx, const char *what, int n_bots,
		     const char **model, char *name, size_t cap);
/* scene:teams()'s list, {name, size, model, index} each, pushed. */
void evo_lua_push_teams(lua_State *L);
/* scene:winner([team]) at stack index 2, for either scene: with no
 * argument, pushes the name of team `winner` (or nil) and returns -2;
 * else returns the new winner (-1 for nil). */
int evo_lua_winner(lua_State *L, int winner);

/* ---- lua_swarm.c: the swarm sensors, lights and patches of both worlds
 * (sim/scene/swarm.h) ---------------------------------------------------- */

/* aperture (degrees), range, slot, read, index (1 based), occluded and
 * scale of the options table at idx into s (its values the defaults). */
void evo_lua_swarm_sensor(lua_State *L, int idx, const char *what,
			  int camera, evo_swarm_sensor *s);
/* scene:colour(handle, name): the colour at stack index 3 given to a
 * light, bot or element, for cameras. */
void evo_lua_set_colour(lua_State *L, evo_blob_kind kind, int index,
			evo_swarm *w, evo_err *err);
/* scene:light{x, y[, z], intensity, colour} and scene:patch{...} of the options
 * table at idx, into w; dims 2 or 3 says which keys a patch takes. */
void evo_lua_add_light(lua_State *L, int idx, int dims, evo_swarm *w,
		       evo_err *err);
void evo_lua_add_patch(lua_State *L, int idx, int dims, evo_swarm *w,
		       evo_err *err);
int evo_lua_bot_sensor_index(lua_State *L, int bot, const char *name,
			     const char *what);
/* Turn a scene error (r < 0) into a Lua error at the caller's line. */
int evo_lua_scene_result(lua_State *L, int r);

/* ---- the methods of the four classes --------------------------------- */

/* Set the methods of each class into the table on the top of the stack:
 * the scene's (lua_scene.c, with lua_scoring.c's rewards, controls and
 * metrics), a bot's (lua_bot.c), an element's and a metric's
 * (lua_element.c). The kinds of scene:NAME and bot:NAME come from
 * sim/scene/kinds.c's rows, each a method in either world; called in a
 * scene of a dimension its row lacks, one raises an error that says so. */
void evo_lua_scene_methods(lua_State *L);
void evo_lua_bot_methods(lua_State *L);
void evo_lua_element_methods(lua_State *L);
void evo_lua_metric_methods(lua_State *L);
/* scene:reward, scene:control, scene:reset_rewards, scene:metric
 * (lua_scoring.c) */
int evo_lua_scene_reward(lua_State *L);
int evo_lua_scene_control(lua_State *L);
int evo_lua_scene_reset_rewards(lua_State *L);
int evo_lua_scene_metric(lua_State *L);

/* ---- the dimensions: lua_dim2d.c, lua_dim3d.c -------------------------- */

/* A bot's sensor as the methods see it. */
typedef struct evo_lua_sensor {
	const char *name;
	int kind;   /* evo_sense_kind */
	int target; /* an element or EVO_TARGET_* */
} evo_lua_sensor;

/* What bot:counts() says. */
typedef struct evo_lua_counts {
	int touching, collisions, delivered, gathered, holding;
	double reward;
} evo_lua_counts;

/* What differs between a 2D and a 3D scene, as the methods need it: one
 * table of functions per dimension. Functions of L read the options
 * table at stack index 2 (its keys already checked against the kind's
 * row) and raise on a bad value. */
struct evo_lua_dim {
	unsigned dim;	   /* EVO_DIM_2D or EVO_DIM_3D */
	const char *words; /* "2D" or "3D" */
	int coords;	   /* the numbers of a position: 2 or 3 */
	int named_targets; /* targets may be "nearest_object" and the like */
	long min_ticks;	   /* the least NextOnTimeout takes */
	void (*view)(evo_lua *l, evo_lua_view *v);
	const char *const *bot_keys;   /* scene:bot's options */
	/* bot:place{...}'s options; NULL: a bot is placed by numbers only,
	 * bot:place(x, y, angle) */
	const char *const *place_keys;
	/* scene:bot: a bot of the model's table at 3 and the options at 2,
	 * named name, of team (-1: none); its index */
	int (*add_bot)(lua_State *L, int team, const char *name,
		       const char *what);
	/* scene:NAME: an element of piece kind k (evo_piece_kind, one of
	 * this world's, scene/element.h), or a piece of kind that is no
	 * element; the element's index */
	int (*add_element)(lua_State *L, int kind, const char *what);
	void (*add_part)(lua_State *L, int kind, const char *what);
	/* bot:NAME: a sensor (evo_sense_kind) or actuator (evo_act_kind);
	 * its index */
	int (*add_sensor)(lua_State *L, int bot, int kind, const char *what);
	int (*add_actuator)(lua_State *L, int bot, int kind, const char *what);
	int (*add_reward)(evo_lua *l, const evo_reward_def *d);
	int (*add_control)(evo_lua *l, const evo_control_def *d);
	/* names and lookups: a bot or element by name (-1: none); a bot's
	 * name, with its team in *team; its sensors' count, and sensor s
	 * into *out when s is one of them; the command of its actuator
	 * name into *c (-1: no such actuator) */
	int (*find)(const evo_lua *l, const char *name, int element);
	const char *(*bot)(const evo_lua *l, int bot, int *team);
	const char *(*element_name)(const evo_lua *l, int e);
	int (*sensor)(const evo_lua *l, int bot, int s, evo_lua_sensor *out);
	int (*command)(const evo_lua *l, int bot, const char *name, double *c);
	/* reading and moving */
	void (*set_target)(lua_State *L, int bot, int s, int target);
	double (*sample)(evo_lua *l, int bot, int s);
	void (*pose)(const evo_lua *l, int bot, double p[3], double *yaw);
	void (*start)(const evo_lua *l, int bot, double p[3], double *yaw);
	int (*place_bot)(evo_lua *l, int bot, const double p[3], double yaw);
	void (*counts)(const evo_lua *l, int bot, evo_lua_counts *c);
	void (*element_pos)(const evo_lua *l, int e, double p[3]);
	/* why element e may not move, or NULL */
	const char *(*element_fixed)(const evo_lua *l, int e);
	void (*place_element)(evo_lua *l, int e, const double p[3]);
	int (*element_active)(const evo_lua *l, int e);
	/* until the next reset: an object off the world, a zone or target
	 * no sensor or reward sees */
	void (*set_element_active)(evo_lua *l, int e, int on);
};

extern const evo_lua_dim evo_lua_dim2d;
extern const evo_lua_dim evo_lua_dim3d;

/* The functions of a dimension's table that read the same fields in
 * either scene, written once (as tasksim/simscene.c's): SC is the
 * evo_lua's scene (sc, sc3), SCENE the prefix of its scene's functions,
 * FIND_ACTUATOR its lookup of a bot's actuator by name; the bots are the
 * one evo_bot of both worlds (scene/bot.h). */
#define EVO_LUA_DIM_COMMON(SC, SCENE, FIND_ACTUATOR)                         \
	static void view(evo_lua *l, evo_lua_view *v)                         \
	{                                                                     \
		*v = (evo_lua_view){                                          \
		    &l->SC->tick,	 &l->SC->rng,	     &l->SC->n_bots,          \
		    &l->SC->n_elements, &l->SC->n_rewards, &l->SC->n_metrics,     \
		    &l->SC->reward,	 l->SC->metric,	     &l->SC->swarm,           \
		    &l->SC->err,	 &l->SC->episode_reward, &l->SC->winner,      \
		    &l->SC->grid_seed};                                       \
	}                                                                     \
	static int add_reward(evo_lua *l, const evo_reward_def *d)            \
	{                                                                     \
		return SCENE##_add_reward(l->SC, d);                          \
	}                                                                     \
	static int add_control(evo_lua *l, const evo_control_def *d)          \
	{                                                                     \
		return SCENE##_add_control(l->SC, d);                         \
	}                                                                     \
	static int find(const evo_lua *l, const char *name, int element)      \
	{                                                                     \
		return element ? evo_scene_find_element(l->SC, name)          \
			       : evo_scene_find_bot(l->SC, name);             \
	}                                                                     \
	static const char *bot(const evo_lua *l, int i, int *team)           \
	{                                                                     \
		*team = l->SC->bot[i].team;                                   \
		return l->SC->bot[i].name;                                    \
	}                                                                     \
	static const char *element_name(const evo_lua *l, int e)              \
	{                                                                     \
		return l->SC->element[e].name;                                \
	}                                                                     \
	static int sensor(const evo_lua *l, int i, int s, evo_lua_sensor *out) \
	{                                                                     \
		const evo_bot *b = &l->SC->bot[i];                            \
		if (s >= 0 && s < b->n_sensors)                               \
			*out = (evo_lua_sensor){b->sensor[s].name,            \
						(int)b->sensor[s].def.kind,   \
						b->sensor[s].def.target};     \
		return b->n_sensors;                                          \
	}                                                                     \
	static int command(const evo_lua *l, int i, const char *name,         \
			   double *c)                                         \
	{                                                                     \
		int a = FIND_ACTUATOR(&l->SC->bot[i], name);                  \
		if (a >= 0)                                                   \
			*c = l->SC->bot[i].actuator[a].command;               \
		return a;                                                     \
	}

/* The fields of a dimension's table its file fills with functions of
 * the same names. */
#define EVO_LUA_DIM_FUNCTIONS                                                 \
	.view = view, .add_bot = add_bot, .add_element = add_element, .add_part = add_part,             \
	.add_sensor = add_sensor, .add_actuator = add_actuator,               \
	.add_reward = add_reward, .add_control = add_control,                 \
	.find = find, .bot = bot, .element_name = element_name,               \
	.sensor = sensor, .command = command, .set_target = set_target, .sample = sample,       \
	.pose = pose, .start = start, .place_bot = place_bot,                 \
	.counts = counts, .element_pos = element_pos,                         \
	.element_fixed = element_fixed, .place_element = place_element,       \
	.element_active = element_active

/* The options table at idx (none: an empty one put there), its keys
 * checked against keys. */
void evo_lua_options(lua_State *L, int idx, const char *what,
		     const char *const *keys);
/* x, y (and z in 3D) of the table at idx into p (each defaulting to
 * p's). */
void evo_lua_opt_pos(lua_State *L, int idx, double p[3], const char *what);
/* The options a kind's row (sim/scene/kinds.c) takes in the scene's
 * dimension; a kind the dimension lacks is an error naming it and the
 * dimension. */
const char *const *evo_lua_kind_keys(lua_State *L, const evo_kind_row *row,
				     const char *what);
/* The scene's own kind whose row (sense_of[k], for one of n kinds) is
 * kind: rows maps a dimension's kinds to kinds.c's. */
int evo_lua_kind_of(const int *rows, int n, int kind);
/* The `name` option of the table at 2, which a sensor or actuator (noun)
 * needs. */
const char *evo_lua_opt_name(lua_State *L, const char *what, const char *noun);
/* The words of a list option `key` at idx, each one of words[0..n): a
 * mask with bit w for words[w]; *given says whether the option was
 * there. Another word is an error listing them. */
unsigned evo_lua_opt_words(lua_State *L, int idx, const char *key,
			   const char *const *words, int n, const char *what,
			   int *given);
/* Elements, bots, rewards and controls are added in init: made in reset,
 * one more would pile up every episode. */
void evo_lua_in_init(lua_State *L, const char *what);

/* ---- lua_sandbox.c: loading scripts, and what they may use ---------- */

/* The sandbox of a scene state (docs/lua.md, "What a script may use"). */
void evo_lua_open_sandbox(lua_State *L);
/* lua_evo.c: the first refused allocation (ctx an evo_lua): the script's
 * line noted for the message. */
void evo_lua_memory_hit(void *ctx);


/* Find NAME.lua in dir/<mind_sub> (dir NULL: the mind folder), then
 * lua_dir/<lua_sub>; 0, -1 when there is none, or -2 when the one found
 * (in out) is a link to a file outside its folder. */
int evo_lua_find_script(const evo_lua *l, const char *dir, const char *mind_sub,
			const char *lua_sub, const char *name, char *out,
			size_t cap);
/* Run a script file and leave its single result, a table, on the stack;
 * raises otherwise. */
void evo_lua_run_file(lua_State *L, const char *path, const char *what);
/* Load the bot model file (docs/lua.md, bot models), looked for in dir's
 * Bots/ first (NULL: the mind folder's); leaves the model's table on the
 * stack. */
int evo_lua_load_model(lua_State *L, evo_lua *l, const char *model,
		       const char *dir);

/* The reset functions of Lua rewards and controls (scene:reward(fn,
 * {reset = f})), in the registry under these keys' addresses: a list of
 * functions each. */
extern const char evo_lua_reward_resets_key;
extern const char evo_lua_control_resets_key;

/* A Lua reward's or control's options at 3, {reset = f, bot = b, team =
 * NAME} (bot and team for a reward only; nil: none): f goes on the list
 * under resets_key (lua_scene.c, for both dimensions). */
void evo_lua_function_options(lua_State *L, const char *what,
			      const void *resets_key, int reward);

/* Call every function of the list under key with the scene, inside the
 * call under way (from a scene method) or as a call of its own with the
 * reset budget. 0, or -1 with err set. */
int evo_lua_call_resets(evo_lua *l, const void *key, evo_err *err);

/* ---- lua_hooks.c: Lua called from the tick ---------------------------- */

/* lua_pcall under the limits (docs/lua.md, "Limits"): an instruction
 * budget and a time limit (both times LUABUDGET), the state's memory
 * limit, and the stop flag. What the call is ("init", "post_step", "a
 * reward function") names it in the message when the script reaches one,
 * "FILE:LINE: the script ran past its budget of N instructions in WHAT;
 * ...", which is then the error on the stack, and stays the error of
 * every later call. Any error value becomes a message with the script's
 * line. A call from within a call shares the outer one's limits. Returns
 * lua_pcall's status. */
int evo_lua_pcall(evo_lua *l, int nargs, int nresults, long budget,
		  double time_limit, const char *what);
/* Note the script's file:line at level for the watchdog (0 in a hook, 1
 * in a C function called from the script). */
void evo_lua_note_where(evo_lua *l, lua_State *L, int level);

/* The scene's hooks (scene/scoring.h), for a scene of either dimension:
 * a Lua reward or control function, the environment's post_step. */
int evo_lua_hook_reward(void *c, evo_err *err, const evo_reward *r,
			double *out);
int evo_lua_hook_control(void *c, evo_err *err, const evo_control *ctl,
			 int *next);
int evo_lua_hook_post_step(void *c, evo_err *err);
/* The scene's tick, whatever its dimension. */
static inline long evo_lua_tick(const evo_lua *l)
{
	return *l->v.tick;
}

/* The scene's metrics (scene/scoring.h), whatever its dimension: the
 * array, with its count in *n, and the scene's error in *err. */
static inline evo_metric *evo_lua_metrics(evo_lua *l, int **n, evo_err **err)
{
	*n = l->v.n_metrics;
	*err = l->v.err;
	return l->v.metric;
}
/* Call env[name](scene, arg) if the environment has it: with_arg 0 no
 * argument, 1 the integer arg, 2 the task's table. 0, or -1 with err. */
int evo_lua_call_env(evo_lua *l, const char *name, int with_arg,
		     lua_Integer arg, evo_err *err);

#endif
