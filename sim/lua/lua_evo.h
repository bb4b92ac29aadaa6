/* evo — the Lua 5.4 layer of a scene: the `evo` module through which bot
 * models (BOTMODEL) and environments (ENV) build a scene, and the hooks
 * that let a Lua function act as a reward or control function.
 *
 * One Lua state per scene, never shared between threads. A bot model or
 * environment named NAME is looked up first in the mind folder (Bots/NAME.lua,
 * Envs/NAME.lua), then in evo's lua/ folder (lua/bots/, lua/envs/).
 * docs/lua.md describes the module. */
#ifndef EVO_LUA_EVO_H
#define EVO_LUA_EVO_H

#include "base/err.h"
#include "evo/evo.h"
#include "world2d/scene.h"
#include "world3d/scene3d.h"

typedef struct evo_lua evo_lua;

/* A team of the task (docs/teams.md), as the environment sees it. */
typedef struct evo_lua_team {
	const char *name;
	const char *botmodel;
	const char *mind_dir; /* its bot model is looked for here first */
	int size;
} evo_lua_team;

typedef struct evo_lua_def {
	/* the scene the scripts build (not owned): a 2D scene, or a 3D one
	 * (DEMO3DSIM, LEARN3DSIM; docs/world3d.md) */
	evo_scene *scene;
	evo_scene3d *scene3d;
	const char *mind_dir; /* searched first; may be NULL */
	const char *lua_dir;  /* evo's lua/ folder; NULL: evo_lua_dir() */
	const char *botmodel; /* BOTMODEL */
	const evo_simbatch *task; /* handed to env.init as a table; may be NULL */
	/* The task's teams (scene:teams(), scene:bot{team = ...}); none in a
	 * one-agent task. Copied. At most EVO_SCENE_MAX_TEAMS. */
	const evo_lua_team *teams;
	int n_teams;
} evo_lua_def;

/* The lua/ folder evo uses: $EVO_LUA_DIR, else lua/ beside the folder of
 * the evo program (a build tree), else share/evo/lua under its prefix. */
const char *evo_lua_dir(void);

/* Point a Lua state's `require` at mind_dir (the mind folder, or "." when
 * empty) first, then at lua_dir, and at no C modules. */
struct lua_State;
void evo_lua_set_path(struct lua_State *L, const char *mind_dir,
		      const char *lua_dir);

/* A Lua state with the evo module, ready to load an environment. Sets
 * the scene's hooks. NULL with err set on failure. */
evo_lua *evo_lua_create(const evo_lua_def *def, evo_err *err);
void evo_lua_destroy(evo_lua *l);

/* Load environment `env` and run its init(scene, task), which adds the
 * bots (built by the bot model), elements, rewards and controls. Returns
 * 0, or -1 with err set to "file:line: message". */
int evo_lua_init_env(evo_lua *l, const char *env, evo_err *err);

/* After evo_scene_reset: the environment's reset(scene, episode), if it
 * has one. */
int evo_lua_reset(evo_lua *l, int episode, evo_err *err);

/* The file the environment and the bot model were loaded from. */
const char *evo_lua_env_path(const evo_lua *l);
const char *evo_lua_bot_path(const evo_lua *l);

#endif
