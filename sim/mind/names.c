/* Names a task gives, checked against the folders (sim/mind/names.h). */
#define _POSIX_C_SOURCE 200809L
#include "mind/names.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "base/fileio.h"

#define MAX_CANDIDATES 256

unsigned evo_task_key_line(const evo_simbatch *sb, const char *key)
{
	for (unsigned i = 0; i < sb->n_pairs; i++)
		if (strcmp(sb->pair[i].key, key) == 0)
			return sb->pair[i].line;
	return 0;
}

/* Add dir's entries (files NAME<suffix>, or subfolders when suffix is
 * NULL) to names; returns the new count. */
static int gather(const char *dir, const char *suffix,
		  char names[][EVO_NAME_MAX], int n)
{
	DIR *d = opendir(dir);
	if (!d)
		return n;
	struct dirent *e;
	while (n < MAX_CANDIDATES && (e = readdir(d))) {
		const char *nm = e->d_name;
		size_t len = strlen(nm);
		if (nm[0] == '.')
			continue;
		if (suffix) {
			size_t sl = strlen(suffix);
			if (len <= sl || len - sl >= EVO_NAME_MAX ||
			    strcmp(nm + len - sl, suffix) != 0)
				continue;
			memcpy(names[n], nm, len - sl);
			names[n][len - sl] = 0;
			n++;
		} else {
			char path[1400];
			struct stat st;
			snprintf(path, sizeof path, "%s/%s", dir, nm);
			if (len >= EVO_NAME_MAX || stat(path, &st) ||
			    !S_ISDIR(st.st_mode))
				continue;
			memcpy(names[n++], nm, len + 1);
		}
	}
	closedir(d);
	return n;
}

void evo_names_suggest(char *out, size_t cap, const char *word,
		       const char *const *dirs, int n, const char *suffix)
{
	static char names[MAX_CANDIDATES][EVO_NAME_MAX];
	const char *list[MAX_CANDIDATES];
	int count = 0;
	out[0] = 0;
	for (int i = 0; i < n; i++)
		if (dirs[i])
			count = gather(dirs[i], suffix, names, count);
	for (int i = 0; i < count; i++)
		list[i] = names[i];
	unsigned best;
	const char *pick = evo_closest_name(word, list, (size_t)count, &best);
	size_t wl = strlen(word);
	if (pick && best <= (wl < 4 ? 1u : wl / 3 + 1))
		snprintf(out, cap, "; did you mean %s?", pick);
}

int evo_task_check_master(const evo_simbatch *sb, const char *task_path,
			  const char *root, evo_err *err)
{
	const char *master = evo_simbatch_get(sb, "MASTERSKILL");
	if (!master || !master[0] || strchr(master, '/'))
		return 0; /* the mind folder's loader says what is wrong */
	char path[1400], skills[1200], hint[EVO_NAME_MAX + 32];
	snprintf(path, sizeof path, "%s/Skills/%s/%s.ades", root, master,
		 master);
	if (evo_file_exists(path))
		return 0;
	snprintf(skills, sizeof skills, "%s/Skills", root);
	const char *dirs[1] = {skills};
	evo_names_suggest(hint, sizeof hint, master, dirs, 1, NULL);
	return evo_fail(err,
			"%s:%u: MASTERSKILL: no skill '%s' in %s (no file "
			"%s)%s",
			task_path, evo_task_key_line(sb, "MASTERSKILL"), master,
			skills, path, hint);
}

int evo_task_check_script(const evo_simbatch *sb, const char *task_path,
			  const char *key, const char *what,
			  const char *mind_dir, const char *sub,
			  const char *lua_dir, const char *lua_sub,
			  evo_err *err)
{
	const char *name = evo_simbatch_get(sb, key);
	if (!name || !name[0] || strchr(name, '/'))
		return 0; /* the script loader says what is wrong */
	char own[1200], shipped[1200], a[1400], b[1400];
	snprintf(own, sizeof own, "%s/%s", mind_dir[0] ? mind_dir : ".", sub);
	snprintf(shipped, sizeof shipped, "%s/%s", lua_dir, lua_sub);
	snprintf(a, sizeof a, "%s/%s.lua", own, name);
	snprintf(b, sizeof b, "%s/%s.lua", shipped, name);
	if (evo_file_exists(a) || evo_file_exists(b))
		return 0;
	char hint[EVO_NAME_MAX + 32];
	const char *dirs[2] = {own, shipped};
	evo_names_suggest(hint, sizeof hint, name, dirs, 2, ".lua");
	return evo_fail(err,
			"%s:%u: %s: %s '%s' not found: looked for %s and %s%s",
			task_path, evo_task_key_line(sb, key), key, what, name,
			a, b, hint);
}
