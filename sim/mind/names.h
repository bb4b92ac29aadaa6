/* evo — "did you mean" over the files of a folder: the environments, bot
 * models and skills a task names, so that a misspelt ENV, BOTMODEL or
 * MASTERSKILL is reported at the task's line with the name it was meant
 * to be. */
#ifndef EVO_NAMES_H
#define EVO_NAMES_H

#include <stddef.h>

#include "base/err.h"
#include "evo/formats.h"

/* The line of key in the task, 0 when absent. */
unsigned evo_task_key_line(const evo_simbatch *sb, const char *key);

/* "; did you mean NAME?" into out (cap bytes) for the name closest to
 * word (ignoring case) among the entries of the n folders dirs (NULL
 * ones skipped): with suffix ".lua", the files NAME.lua; with suffix
 * NULL, the subfolders NAME. "" when none is near. */
void evo_names_suggest(char *out, size_t cap, const char *word,
		       const char *const *dirs, int n, const char *suffix);

/* The task's MASTERSKILL has its .ades under root/Skills, else an error
 * at the task's line naming the file looked for and the closest skill
 * folder ("avoid" for "Avoid"). 0 or -1 with err. */
int evo_task_check_master(const evo_simbatch *sb, const char *task_path,
			  const char *root, evo_err *err);

/* The script the task's key (ENV, BOTMODEL) names, NAME.lua in
 * mind_dir/sub or lua_dir/lua_sub, exists; else an error at the task's
 * line saying what (`what`: "environment", "bot model") was looked for
 * where, with the closest name of both folders. 0 or -1 with err. */
int evo_task_check_script(const evo_simbatch *sb, const char *task_path,
			  const char *key, const char *what,
			  const char *mind_dir, const char *sub,
			  const char *lua_dir, const char *lua_sub,
			  evo_err *err);

#endif
