/* .simbatch: a task (tutorial chapter 4). KEY:VALUE pairs in any order;
 * keys evo does not know are skipped with a warning, as the tutorial asks
 * superfluous parameters to be ignored. Keys of a learning method
 * (NEAT_*, GA_*, SA_*, CMAES_*, NOVELTY_*, MAPELITES_*, OPEN_*) are all kept: the
 * method itself knows its settings and warns about the ones it does not
 * (docs/learning.md). */
#include "evo/formats.h"
#include "text.h"

const char *const evo_task_types[] = {
    "DEMOSIM",	      "LEARNSIM",	"LEARNSIMCONTINUOUS",
    "DEMO2DSIMMULTI", "LEARN2DSIMMULTI", "DEMO3DSIM",
    "LEARN3DSIM",     "DEMO3DSIMMULTI",	"LEARN3DSIMMULTI",
    "DEMOREMOTE",     "DEMOREMOTESIM",	"LEARNREMOTESIM",
    "OPENENDED",      NULL};

static const char *const methods[] = {"NEAT",	 "GENETIC", "ANNEALING", "CMAES",
				      "NOVELTY", "MAPELITES", NULL};
static const char *const genomes[] = {"HOMOGENEOUS", "HETEROGENEOUS", NULL};
static const char *const fitnesses[] = {"TEAM", "OWN", NULL};
static const char *const pole_protocols[] = {"NEAT", "GOMEZ", NULL};

#define MILLION 1000000
#define TEXT(k)	{k, EVO_KEY_TEXT, 0, 0, 0, 0, NULL, 0}
#define WHOLE(k, lo, hi) {k, EVO_KEY_WHOLE, lo, hi, 0, 0, NULL, 0}
#define WORD(k, w) {k, EVO_KEY_WORD, 0, 0, 0, 0, w, 0}

/* Every key evo knows, and the values it takes. The ranges are wide enough
 * that no real task meets them, and narrow enough that no value reaches an
 * allocation or a loop that would not end in time and memory: a
 * population of 10,000 networks of evo's largest size, a hidden layer of
 * no more nodes than one node may have links into it
 * (EVO_NET_MAX_FANIN), at most 1,000 repetitions of at most 10,000,000
 * ticks. docs/formats.md says them all, and tests/docs/test_defaults.c
 * checks that it says them as this table does. */
const evo_simbatch_key_def evo_simbatch_key_defs[] = {
    WORD("TYPE", evo_task_types),
    TEXT("BOTMODEL"),
    TEXT("BOTNAME"),
    TEXT("MASTERSKILL"),
    TEXT("LEARNINGSKILL"),
    TEXT("ENV"),
    WORD("LEARNINGMETHOD", methods),
    TEXT("ROOTFOLDER"),
    WHOLE("NUMGEN", 1, MILLION),
    WHOLE("EVALREP", 1, 1000),
    WHOLE("TICKLIM", 1, 10 * MILLION),
    WHOLE("POPSIZE", 1, 10000),
    WHOLE("SEED", 0, 2147483647),
    WHOLE("THREADS", 1, EVO_MAX_THREADS),
    WHOLE("HIDDEN", 1, EVO_NET_MAX_FANIN),
    /* fitness is a sum of rewards: a million million is out of reach */
    {"TARGETFITNESS", EVO_KEY_DECIMAL, -(int64_t)MILLION * MILLION * MILLION,
     (int64_t)MILLION * MILLION * MILLION, 0, 0, NULL, 0},
    TEXT("LCMURL"),
    {"REMOTENAME", EVO_KEY_NAME, 1, EVO_KEY_NAME_MAX, 0, 0, NULL, 0},
    TEXT("LCMKEYFILE"),
    /* seconds, more than 0 and at most an hour */
    {"REMOTETIMEOUT", EVO_KEY_DECIMAL, 0, (int64_t)3600 * MILLION, 1, 0,
     NULL, 0},
    TEXT("CANURL"),
    TEXT("TEAM"),
    TEXT("LEARNINGTEAM"),
    WORD("TEAMGENOME", genomes),
    WORD("TEAMFITNESS", fitnesses),
    WHOLE("ALTERNATE", 1, MILLION),
    TEXT("SKILLORDER"),
    WHOLE("ROUNDS", 1, MILLION),
    WHOLE("VALIDATION", 1, 1000),
    WHOLE("LUABUDGET", 1, 1000),
    WHOLE("LUAMEMORY", 16, 65536),
    WORD("POLEPROTOCOL", pole_protocols),
    {NULL, EVO_KEY_TEXT, 0, 0, 0, 0, NULL, 0},
};

const evo_simbatch_key_def *evo_simbatch_key_find(const char *key)
{
	for (const evo_simbatch_key_def *d = evo_simbatch_key_defs; d->name;
	     d++)
		if (evo_txt_ieq(d->name, key))
			return d;
	return NULL;
}

/* The known key closest to key, for "did you mean". */
static const char *closest_key(evo_txt_slice key)
{
	const char *best = evo_simbatch_key_defs[0].name;
	unsigned best_d = ~0u;
	for (const evo_simbatch_key_def *d = evo_simbatch_key_defs; d->name;
	     d++) {
		unsigned dist = evo_txt_distance(key, d->name);
		if (dist < best_d) {
			best = d->name;
			best_d = dist;
		}
	}
	return best;
}

/* A team task lists its teams, one TEAM line each (docs/teams.md): the
 * one key that may be given more than once. */
static int repeatable(const char *key)
{
	return evo_txt_eq(key, "TEAM");
}

/* The prefixes of the learning methods' own keys. */
static const char *const method_prefixes[] = {
    "NEAT_", "GA_", "SA_", "CMAES_", "NOVELTY_", "MAPELITES_", "OPEN_", NULL};

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

static void warn(evo_simbatch *out, const evo_txt_entry *e, const char *file)
{
	if (out->n_warnings < EVO_MAX_WARNINGS)
		evo_txt_diag(&out->warning[out->n_warnings], file, e->line,
			     "unknown key '%.*s' ignored; did you mean %s?",
			     EVO_TXT_Q(e->field[0]), closest_key(e->field[0]));
	if (out->n_warnings < UINT32_MAX)
		out->n_warnings++;
}

/* v millionths as a decimal ("-1.5", "3600") into buf; its length. */
static size_t decimal_text(int64_t v, char *buf, size_t cap)
{
	char tmp[32];
	size_t n = 0, out = 0;
	uint64_t u = v < 0 ? (uint64_t)0 - (uint64_t)v : (uint64_t)v;
	uint64_t whole = u / MILLION, frac = u % MILLION;
	int digits = 6;
	while (frac && frac % 10 == 0) {
		frac /= 10;
		digits--;
	}
	if (frac)
		for (int i = 0; i < digits; i++) {
			tmp[n++] = (char)('0' + frac % 10);
			frac /= 10;
		}
	if (n)
		tmp[n++] = '.';
	do {
		tmp[n++] = (char)('0' + whole % 10);
		whole /= 10;
	} while (whole);
	if (v < 0)
		tmp[n++] = '-';
	while (n && out + 1 < cap)
		buf[out++] = tmp[--n];
	if (cap)
		buf[out] = 0;
	return out;
}

size_t evo_simbatch_key_range(const evo_simbatch_key_def *d, char *buf,
			      size_t cap)
{
	char lo[32], hi[32];
	size_t n = 0;
	if (!cap)
		return 0;
	buf[0] = 0;
	switch (d->kind) {
	case EVO_KEY_WHOLE:
		decimal_text(d->lo * MILLION, lo, sizeof lo);
		decimal_text(d->hi * MILLION, hi, sizeof hi);
		return evo_txt_fmt(buf, cap, "a whole number from %s to %s", lo,
				   hi);
	case EVO_KEY_DECIMAL:
		decimal_text(d->lo, lo, sizeof lo);
		decimal_text(d->hi, hi, sizeof hi);
		if (!d->above && !d->below)
			return evo_txt_fmt(buf, cap, "a number from %s to %s",
					   lo, hi);
		return evo_txt_fmt(buf, cap, "a number %s %s and %s %s",
				   d->above ? "above" : "of at least", lo,
				   d->below ? "below" : "at most", hi);
	case EVO_KEY_WORD:
		for (unsigned i = 0; d->words[i]; i++)
			n += evo_txt_fmt(buf + n, cap - n, "%s%s",
					 i == 0		      ? ""
					 : d->words[i + 1] ? ", "
							   : " or ",
					 d->words[i]);
		return n;
	case EVO_KEY_NAME:
		return evo_txt_fmt(buf, cap,
				   "names of 1 to %u letters, digits, '_' or "
				   "'-', joined by ','",
				   (unsigned)d->hi);
	case EVO_KEY_TEXT:
		break;
	}
	return evo_txt_fmt(buf, cap, "text of at most %u bytes",
			   (unsigned)(EVO_VALUE_MAX - 1));
}

/* A decimal [-]digits[.digits] (at least one digit, at most 6 after the
 * point) in millionths: 0; -1 when v is not one; -2 when it is one too
 * large for any range (more than 13 digits before the point). */
static int decimal_value(evo_txt_slice v, int64_t *out)
{
	size_t i = 0;
	int neg = 0, whole = 0, frac = 0;
	uint64_t u = 0; /* 13 digits and 6 decimals fit */
	if (i < v.len && v.s[i] == '-') {
		neg = 1;
		i++;
	}
	for (; i < v.len && v.s[i] >= '0' && v.s[i] <= '9'; i++, whole++)
		if (whole < 13)
			u = u * 10 + (uint64_t)(v.s[i] - '0');
	if (i < v.len && v.s[i] == '.')
		for (i++; i < v.len && v.s[i] >= '0' && v.s[i] <= '9';
		     i++, frac++)
			if (frac < 6)
				u = u * 10 + (uint64_t)(v.s[i] - '0');
	if (i != v.len || whole + frac == 0 || frac > 6)
		return -1;
	if (whole > 13)
		return -2;
	for (; frac < 6; frac++)
		u *= 10;
	if (u > (uint64_t)INT64_MAX)
		return -2;
	*out = neg ? -(int64_t)u : (int64_t)u;
	return 0;
}

/* A value within d's range: 1, else 0. */
static int value_ok(const evo_simbatch_key_def *d, evo_txt_slice v)
{
	int64_t x;
	uint32_t n;
	switch (d->kind) {
	case EVO_KEY_WHOLE:
		return evo_txt_uint(v, (uint32_t)d->hi, &n) == 0 &&
		       (int64_t)n >= d->lo;
	case EVO_KEY_DECIMAL:
		return decimal_value(v, &x) == 0 &&
		       (d->above ? x > d->lo : x >= d->lo) &&
		       (d->below ? x < d->hi : x <= d->hi);
	case EVO_KEY_WORD:
		for (unsigned i = 0; d->words[i]; i++)
			if (evo_txt_slice_ieq(v, d->words[i]))
				return 1;
		return 0;
	case EVO_KEY_NAME: {
		/* names joined by ',', none empty, none past hi */
		size_t run = 0;
		for (size_t i = 0; i <= v.len; i++) {
			char c = i < v.len ? v.s[i] : ',';
			if (c == ',') {
				if (run < 1 || run > (size_t)d->hi)
					return 0;
				run = 0;
			} else if ((c >= 'a' && c <= 'z') ||
				   (c >= 'A' && c <= 'Z') ||
				   (c >= '0' && c <= '9') || c == '_' ||
				   c == '-') {
				run++;
			} else {
				return 0;
			}
		}
		return 1;
	}
	case EVO_KEY_TEXT:
		break;
	}
	return 1;
}

int evo_simbatch_key_ok(const evo_simbatch_key_def *d, const char *value)
{
	evo_txt_slice v = {value, evo_txt_len(value)};
	return value_ok(d, v);
}

/* "FILE:LINE: KEY: expected RANGE, found 'VALUE'", and for a word the
 * closest one. A method's key (no definition) is the method's to check. */
static evo_status check_value(const evo_simbatch_key_def *d, evo_txt_slice v,
			      const evo_txt_entry *e, const char *file,
			      evo_diag *err)
{
	char range[320];
	if (!d || value_ok(d, v))
		return EVO_OK;
	evo_simbatch_key_range(d, range, sizeof range);
	if (d->secret) {
		evo_txt_diag(err, file, e->line,
			     "%s: expected %s, found a value of %u bytes",
			     d->name, range, (unsigned)v.len);
		return EVO_ERR_SYNTAX;
	}
	if (d->kind == EVO_KEY_WORD) {
		evo_txt_diag(err, file, e->line,
			     "%s: expected %s, found '%.*s'; did you mean %s?",
			     d->name, range, EVO_TXT_Q(v),
			     evo_txt_closest(v, d->words, 0));
		return EVO_ERR_NAME;
	}
	evo_txt_diag(err, file, e->line, "%s: expected %s, found '%.*s'",
		     d->name, range, EVO_TXT_Q(v));
	/* a number out of range is a limit; anything else, bad syntax */
	uint32_t n;
	int64_t x;
	if (d->kind == EVO_KEY_WHOLE)
		return evo_txt_uint(v, (uint32_t)d->hi, &n) == -2
			   ? EVO_ERR_LIMIT
			   : EVO_ERR_SYNTAX;
	if (d->kind == EVO_KEY_DECIMAL)
		return decimal_value(v, &x) == -1 ? EVO_ERR_SYNTAX
						  : EVO_ERR_LIMIT;
	return EVO_ERR_SYNTAX;
}

static evo_status add_pair(evo_simbatch *out, const evo_txt_entry *e,
			   const char *file, evo_diag *err)
{
	/* A pointer, not a copy: gcc -Os turns a struct copy into memcpy. */
	const evo_txt_slice *key = &e->field[0];
	evo_txt_slice value;
	const char *known = NULL;
	const evo_simbatch_key_def *def = NULL;
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
	for (def = evo_simbatch_key_defs; def->name; def++)
		if (evo_txt_slice_ieq(*key, def->name))
			break;
	if (def->name)
		known = def->name;
	else
		def = NULL;
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
	st = check_value(def, value, e, file, err);
	if (st != EVO_OK)
		return st;
	p = &out->pair[out->n_pairs];
	if (evo_txt_copy(p->value, sizeof p->value, value) != 0) {
		if (def && def->secret) {
			evo_txt_diag(err, file, e->line,
				     "expected a value of at most %u bytes for "
				     "%s, found %u bytes",
				     (unsigned)(EVO_VALUE_MAX - 1), known,
				     (unsigned)value.len);
			return EVO_ERR_LIMIT;
		}
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
