/* .simbatch: a task (tutorial chapter 4). KEY:VALUE pairs in any order;
 * keys evo does not know are skipped with a warning, as the tutorial asks
 * superfluous parameters to be ignored. Keys of a learning method
 * (NEAT_*, GA_*, SA_*) are all kept: the method itself knows its settings
 * and warns about the ones it does not (docs/learning.md). */
#include "evo/formats.h"
#include "text.h"

const char *const evo_simbatch_keys[] = {"TYPE",
					 "BOTMODEL",
					 "BOTNAME",
					 "MASTERSKILL",
					 "LEARNINGSKILL",
					 "ENV",
					 "LEARNINGMETHOD",
					 "ROOTFOLDER",
					 "NUMGEN",
					 "EVALREP",
					 "TICKLIM",
					 "POPSIZE",
					 "SEED",
					 "THREADS",
					 "HIDDEN",
					 "TARGETFITNESS",
					 "LCMURL",
					 "REMOTENAME",
					 "REMOTETIMEOUT",
					 "CANURL",
					 "TEAM",
					 "LEARNINGTEAM",
					 "TEAMGENOME",
					 "TEAMFITNESS",
					 "ALTERNATE",
					 "SKILLORDER",
					 "ROUNDS",
					 "VALIDATION",
					 "LUABUDGET",
					 "LUAMEMORY",
					 NULL};

/* A team task lists its teams, one TEAM line each (docs/teams.md): the
 * one key that may be given more than once. */
static int repeatable(const char *key)
{
	return evo_txt_eq(key, "TEAM");
}

/* The prefixes of the learning methods' own keys. */
static const char *const method_prefixes[] = {"NEAT_", "GA_", "SA_", NULL};

/* 1 when key starts with a method's prefix and has a name after it. */
static int method_key(evo_txt_slice key)
{
	for (unsigned p = 0; method_prefixes[p]; p++) {
		size_t n = 0;
		while (method_prefixes[p][n] && n < key.len &&
		       evo_txt_upper(key.s[n]) == method_prefixes[p][n])
			n++;
		if (!method_prefixes[p][n] && key.len > n)
			return 1;
	}
	return 0;
}

const char *const evo_task_types[] = {
    "DEMOSIM",	       "LEARNSIM",	 "LEARNSIMCONTINUOUS", "DEMO2DSIMMULTI",
    "LEARN2DSIMMULTI", "DEMO3DSIM",	 "LEARN3DSIM",	       "DEMOREMOTE",
    "DEMOREMOTESIM",   "LEARNREMOTESIM", "OPENENDED",	       NULL};

#define WHOLE_MAX 2147483647u /* whole-number values fit an int */

/* The smallest value a whole-number key takes, or -1 for other keys. */
static int whole_min(const char *key)
{
	if (evo_txt_eq(key, "NUMGEN") || evo_txt_eq(key, "EVALREP") ||
	    evo_txt_eq(key, "TICKLIM") || evo_txt_eq(key, "POPSIZE") ||
	    evo_txt_eq(key, "THREADS") || evo_txt_eq(key, "HIDDEN") ||
	    evo_txt_eq(key, "ALTERNATE") || evo_txt_eq(key, "ROUNDS") ||
	    evo_txt_eq(key, "VALIDATION"))
		return 1;
	if (evo_txt_eq(key, "SEED"))
		return 0;
	return -1;
}

static void warn(evo_simbatch *out, const evo_txt_entry *e, const char *file)
{
	if (out->n_warnings < EVO_MAX_WARNINGS)
		evo_txt_diag(
		    &out->warning[out->n_warnings], file, e->line,
		    "unknown key '%.*s' ignored; did you mean %s?",
		    EVO_TXT_Q(e->field[0]),
		    evo_txt_closest(e->field[0], evo_simbatch_keys, 0));
	if (out->n_warnings < UINT32_MAX)
		out->n_warnings++;
}

static evo_status check_value(const char *key, evo_txt_slice v,
			      const evo_txt_entry *e, const char *file,
			      evo_diag *err)
{
	int min = whole_min(key);
	uint32_t n;
	if (min >= 0) {
		int r = evo_txt_uint(v, WHOLE_MAX, &n);
		if (r != 0 || n < (uint32_t)min) {
			evo_txt_diag(err, file, e->line,
				     "expected a whole number %s for %s, found "
				     "'%.*s'",
				     min ? "1..2147483647" : "0..2147483647",
				     key, EVO_TXT_Q(v));
			return r == -2 ? EVO_ERR_LIMIT : EVO_ERR_SYNTAX;
		}
	} else if (evo_txt_eq(key, "TYPE")) {
		size_t i;
		for (i = 0; evo_task_types[i]; i++)
			if (evo_txt_slice_ieq(v, evo_task_types[i]))
				return EVO_OK;
		evo_txt_diag(
		    err, file, e->line,
		    "expected a task type for TYPE, found '%.*s'; did you "
		    "mean %s? (see docs/formats.md for the list)",
		    EVO_TXT_Q(v), evo_txt_closest(v, evo_task_types, 0));
		return EVO_ERR_NAME;
	}
	return EVO_OK;
}

static evo_status add_pair(evo_simbatch *out, const evo_txt_entry *e,
			   const char *file, evo_diag *err)
{
	/* A pointer, not a copy: gcc -Os turns a struct copy into memcpy. */
	const evo_txt_slice *key = &e->field[0];
	evo_txt_slice value;
	const char *known = NULL;
	char method_name[EVO_NAME_MAX];
	evo_simbatch_pair *p;
	evo_status st;
	uint32_t i;

	if (e->n_fields < 2) {
		evo_txt_diag(err, file, e->line,
			     "expected KEY:VALUE, found '%.*s' (no ':')",
			     EVO_TXT_Q(e->text));
		return EVO_ERR_SYNTAX;
	}
	if (key->len == 0) {
		evo_txt_diag(err, file, e->line,
			     "expected a key before ':', found '%.*s'",
			     EVO_TXT_Q(e->text));
		return EVO_ERR_SYNTAX;
	}
	/* The value runs to the end of the entry: a path may hold ':'. */
	value = evo_txt_rest(e, 1);
	if (value.len == 0) {
		evo_txt_diag(err, file, e->line,
			     "expected a value after '%.*s:', found nothing",
			     EVO_TXT_Q(*key));
		return EVO_ERR_SYNTAX;
	}
	for (i = 0; evo_simbatch_keys[i]; i++)
		if (evo_txt_slice_ieq(*key, evo_simbatch_keys[i]))
			known = evo_simbatch_keys[i];
	if (!known && method_key(*key)) {
		/* Kept as written, upper-cased. */
		if (key->len >= EVO_NAME_MAX) {
			evo_txt_diag(
			    err, file, e->line,
			    "expected a key of at most %u bytes, found "
			    "'%.*s'",
			    (unsigned)(EVO_NAME_MAX - 1), EVO_TXT_Q(*key));
			return EVO_ERR_LIMIT;
		}
		for (i = 0; i < key->len; i++)
			method_name[i] = evo_txt_upper(key->s[i]);
		method_name[i] = 0;
		known = method_name;
	}
	if (!known) {
		warn(out, e, file);
		return EVO_OK;
	}
	for (i = 0; i < out->n_pairs && !repeatable(known); i++) {
		if (evo_txt_eq(out->pair[i].key, known)) {
			evo_txt_diag(err, file, e->line,
				     "expected each key once, found %s again "
				     "(first on line %u)",
				     known, (unsigned)out->pair[i].line);
			return EVO_ERR_NAME;
		}
	}
	if (out->n_pairs >= EVO_MAX_SIMBATCH) {
		evo_txt_diag(err, file, e->line,
			     "expected at most %u pairs, found another: '%.*s'",
			     (unsigned)EVO_MAX_SIMBATCH, EVO_TXT_Q(e->text));
		return EVO_ERR_LIMIT;
	}
	st = check_value(known, value, e, file, err);
	if (st != EVO_OK)
		return st;
	p = &out->pair[out->n_pairs];
	if (evo_txt_copy(p->value, sizeof p->value, value) != 0) {
		evo_txt_diag(
		    err, file, e->line,
		    "expected a value of at most %u bytes for %s, found "
		    "'%.*s'",
		    (unsigned)(EVO_VALUE_MAX - 1), known, EVO_TXT_Q(value));
		return EVO_ERR_LIMIT;
	}
	for (i = 0; known[i]; i++)
		p->key[i] = known[i];
	for (; i < sizeof p->key; i++)
		p->key[i] = 0;
	p->line = e->line;
	out->n_pairs++;
	return EVO_OK;
}

evo_status evo_simbatch_parse(const char *buf, size_t len, const char *file,
			      evo_simbatch *out, evo_diag *err)
{
	evo_txt_lexer lx;
	evo_txt_entry e;
	int r;

	out->n_pairs = 0;
	out->n_warnings = 0;
	evo_txt_lex_init(&lx, buf, len, file);
	while ((r = evo_txt_lex_next(&lx, &e, err)) > 0) {
		evo_status st = add_pair(out, &e, file, err);
		if (st != EVO_OK)
			return st;
	}
	return r < 0 ? EVO_ERR_SYNTAX : EVO_OK;
}

const char *evo_simbatch_get(const evo_simbatch *sb, const char *key)
{
	uint32_t i;
	if (!sb || !key)
		return NULL;
	for (i = 0; i < sb->n_pairs && i < EVO_MAX_SIMBATCH; i++)
		if (evo_txt_ieq(sb->pair[i].key, key))
			return sb->pair[i].value;
	return NULL;
}
