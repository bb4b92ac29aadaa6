/* evo — the mind-folder text formats: .botdesc, .vardesc, .ades, .simbatch,
 * and evo's own .net network files.
 *
 * The parsers work on memory buffers; they do no I/O and never allocate.
 * Results go into fixed-capacity structs the caller owns (they are large:
 * allocate them on the heap or statically on a host). Every parser:
 *   - accepts a UTF-8 BOM, CRLF or LF line ends, blank lines, lines whose
 *     first non-blank character is '#', and spaces or tabs around ':';
 *   - reads each line as a sequence of entries: an entry is words joined
 *     by ':' (spaces next to a ':' belong to the entry); other whitespace
 *     separates entries, so "LEARNINGMETHOD: NEAT ROOTFOLDER: Minds/T6"
 *     is two entries;
 *   - on malformed input returns an error status and fills err with
 *     "file:line: what was expected, what was found" (file is the name
 *     the caller passes, used only for messages);
 *   - matches keywords (SENSORS, input, SE, neural, hardCoded, ...)
 *     without regard to case; names (sensors, skills, ...) are
 *     case-sensitive.
 * docs/formats.md is the reference for what each format accepts. */
#ifndef EVO_FORMATS_H
#define EVO_FORMATS_H

#include <stddef.h>
#include <stdint.h>

#include "evo/fixed.h"
#include "evo/status.h"

#define EVO_NAME_MAX 64	    /* bytes in a name, with its NUL */
#define EVO_VALUE_MAX 256   /* bytes in a .simbatch value or sensor params */
#define EVO_MAX_SENSORS 128
#define EVO_MAX_ACTUATORS 64
#define EVO_MAX_VARIABLES 64
#define EVO_MAX_SKILL_IO 64 /* inputs, or outputs, of one skill */
#define EVO_MAX_SIMBATCH 128 /* KEY:VALUE pairs in one .simbatch */
#define EVO_MAX_WARNINGS 16
#define EVO_DIAG_MAX 320

/* A parse error or warning message, "file:line: text". */
typedef struct evo_diag {
	char msg[EVO_DIAG_MAX];
} evo_diag;

/* The name of list (n names) closest to word by edit distance, ignoring
 * ASCII case, for "did you mean" hints; NULL when n is 0. *distance gets
 * the distance when not NULL. */
const char *evo_closest_name(const char *word, const char *const *list,
			     size_t n, unsigned *distance);

/* ---- .botdesc ----------------------------------------------------- */

typedef struct evo_botdesc_entry {
	char name[EVO_NAME_MAX];
	char type[EVO_NAME_MAX];
	char params[EVO_VALUE_MAX]; /* what follows name:type:, or "" */
	uint32_t line;
} evo_botdesc_entry;

typedef struct evo_botdesc {
	uint32_t n_sensors, n_actuators;
	evo_botdesc_entry sensor[EVO_MAX_SENSORS];
	evo_botdesc_entry actuator[EVO_MAX_ACTUATORS];
} evo_botdesc;

/* SENSORS, then name:type(:params) entries; ACTUATORS, then name:type
 * entries. Names are unique across sensors and across actuators. */
evo_status evo_botdesc_parse(const char *buf, size_t len, const char *file,
			     evo_botdesc *out, evo_diag *err);

/* ---- .vardesc ----------------------------------------------------- */

/* Variable types. The numbering is part of the mind image format. */
typedef enum evo_var_type {
	EVO_VAR_PLAIN = 0,   /* VariableModule */
	EVO_VAR_SINWAVE = 1, /* TickWaveSinVariableModule */
	EVO_VAR_COUNTER = 2, /* CounterVariableModule */
	EVO_VAR_TYPE_COUNT
} evo_var_type;

/* The .vardesc spelling of a variable type, or NULL. */
const char *evo_var_type_name(unsigned type);

typedef struct evo_vardesc_entry {
	char name[EVO_NAME_MAX];
	uint8_t type; /* evo_var_type */
	uint32_t line;
} evo_vardesc_entry;

typedef struct evo_vardesc {
	uint32_t n_vars;
	evo_vardesc_entry var[EVO_MAX_VARIABLES];
} evo_vardesc;

/* name:type entries, one per variable; an empty file has no variables. */
evo_status evo_vardesc_parse(const char *buf, size_t len, const char *file,
			     evo_vardesc *out, evo_diag *err);

/* ---- .ades -------------------------------------------------------- */

typedef enum evo_input_type {
	EVO_IN_SE = 0, /* sensor value */
	EVO_IN_SD = 1, /* sensor derivative */
	EVO_IN_VA = 2, /* variable value */
	EVO_IN_VD = 3, /* variable derivative */
} evo_input_type;

typedef enum evo_output_type {
	EVO_OUT_MO = 0, /* command to an actuator */
	EVO_OUT_SK = 1, /* influence to a sub-skill */
	EVO_OUT_VA = 2, /* value to a variable */
} evo_output_type;

typedef enum evo_skill_kind {
	EVO_SKILL_NEURAL = 0,
	EVO_SKILL_HARDCODED = 1,
} evo_skill_kind;

typedef struct evo_ades_io {
	uint8_t type; /* evo_input_type or evo_output_type */
	char name[EVO_NAME_MAX];
	uint32_t line;
} evo_ades_io;

typedef struct evo_ades {
	char name[EVO_NAME_MAX];
	uint32_t n_in, n_out;
	evo_ades_io in[EVO_MAX_SKILL_IO];
	evo_ades_io out[EVO_MAX_SKILL_IO];
	uint8_t kind;	/* evo_skill_kind */
	uint32_t layers; /* neural: hidden layers (layers:N), 1 if absent */
	char hc_class[EVO_NAME_MAX]; /* hardCoded: class:NAME */
	uint32_t kind_line;	     /* line of "neural" or "hardCoded" */
	uint32_t name_line;
} evo_ades;

/* Name; input:N and N TYPE:name lines; output:N and N TYPE:name lines;
 * "neural" with optional layers:N, or "hardCoded" with class:NAME. */
evo_status evo_ades_parse(const char *buf, size_t len, const char *file,
			  evo_ades *out, evo_diag *err);

/* Short names of input and output types ("SE", "MO", ...), or NULL. */
const char *evo_input_type_name(unsigned type);
const char *evo_output_type_name(unsigned type);

/* ---- .simbatch ---------------------------------------------------- */

typedef struct evo_simbatch_pair {
	char key[EVO_NAME_MAX]; /* upper-cased as written */
	char value[EVO_VALUE_MAX];
	uint32_t line;
} evo_simbatch_pair;

typedef struct evo_simbatch {
	uint32_t n_pairs; /* known keys only */
	evo_simbatch_pair pair[EVO_MAX_SIMBATCH];
	uint32_t n_warnings; /* unknown keys; at most EVO_MAX_WARNINGS kept */
	evo_diag warning[EVO_MAX_WARNINGS];
} evo_simbatch;

/* KEY:VALUE entries, any number per line, in any order. Keys are matched
 * without regard to case against evo_simbatch_key_defs; an unknown key is
 * skipped with a warning naming the closest known key. A known key given
 * twice is an error, except TEAM, one line per team (docs/teams.md):
 * evo_simbatch_get gives the first, the pairs hold them all in order. Every
 * value is checked against its key's definition (its kind and range) at its
 * line, so no command reads a value out of range. A learning method's own
 * keys (NEAT_*, GA_*, SA_*, CMAES_*, NOVELTY_*) are kept as text for the
 * method to check (docs/learning.md). */
evo_status evo_simbatch_parse(const char *buf, size_t len, const char *file,
			      evo_simbatch *out, evo_diag *err);

/* The value of key in a parsed .simbatch, or NULL when absent. */
const char *evo_simbatch_get(const evo_simbatch *sb, const char *key);

/* What a .simbatch key's value is. */
typedef enum evo_key_kind {
	EVO_KEY_TEXT,	 /* any text up to EVO_VALUE_MAX - 1 bytes (a name, a
			  * path, a URL): checked where it is used */
	EVO_KEY_WHOLE,	 /* digits only, lo..hi */
	EVO_KEY_DECIMAL, /* [-]digits[.digits], at most 6 decimals, no
			  * exponent; lo..hi in millionths, bounds excluded
			  * where above/below say so */
	EVO_KEY_WORD,	 /* one of words, any case */
	EVO_KEY_NAME,	 /* names of 1..hi letters, digits, '_', '-', joined
			  * by ',' */
} evo_key_kind;

#define EVO_KEY_NAME_MAX 63 /* a remote's name (docs/remote.md) */
#define EVO_MAX_THREADS	 1024 /* THREADS, and --threads */

/* One known .simbatch key: its kind and range. To add a key, add a row to
 * evo_simbatch_key_defs (core/src/parse_simbatch.c) and a row to
 * docs/formats.md's table of keys, whose range column must read as
 * evo_simbatch_key_range renders it (tests/docs/test_defaults.c), and
 * read it with evo_simbatch_get where it is used: its value is then
 * within its range in `evo check`, `evo run` and `evo serve` alike. */
typedef struct evo_simbatch_key_def {
	const char *name;
	evo_key_kind kind;
	int64_t lo, hi;		  /* WHOLE, DECIMAL: the range */
	uint8_t above, below;	  /* DECIMAL: lo, hi excluded */
	const char *const *words; /* WORD: NULL-terminated */
	uint8_t secret;		  /* a key (LCMKEY...): messages never show
				   * its value, only its length */
} evo_simbatch_key_def;

/* The known .simbatch keys, ended by a row whose name is NULL. */
extern const evo_simbatch_key_def evo_simbatch_key_defs[];

/* The definition of key (upper case), or NULL when evo does not know it. */
const evo_simbatch_key_def *evo_simbatch_key_find(const char *key);

/* 1 when value (NUL-terminated) is one d takes, else 0: the check
 * evo_simbatch_parse makes of every value of a known key. */
int evo_simbatch_key_ok(const evo_simbatch_key_def *d, const char *value);

/* The values d takes, in words ("a whole number from 1 to 1024"), into
 * buf (cap bytes, NUL-terminated, cut when too small); returns its
 * length. The messages of evo_simbatch_parse and docs/formats.md say it
 * this way. */
size_t evo_simbatch_key_range(const evo_simbatch_key_def *d, char *buf,
			      size_t cap);

/* The known task types (TYPE:...), NULL-terminated. */
extern const char *const evo_task_types[];

/* ---- .net --------------------------------------------------------- */

#define EVO_NET_MAX_NODES 512	/* hidden + output nodes */
#define EVO_NET_MAX_LINKS 4096
#define EVO_NET_MAX_FANIN 256	/* links into one node */
#define EVO_NET_WEIGHT_MAX 128 /* |weight| and |bias| limit, exclusive */

typedef struct evo_netdesc_node {
	uint16_t id;
	uint8_t act;  /* evo_act */
	evo_q16 bias;
	uint32_t line;
} evo_netdesc_node;

typedef struct evo_netdesc_link {
	uint16_t from, to; /* node ids */
	evo_q16 weight;
	uint32_t line;
} evo_netdesc_link;

/* A network as a set of nodes and links. Ids 0 .. n_in-1 are the inputs
 * (implicit); every other node is listed in node[], and out_id[k] names
 * the node whose activation is output k. */
typedef struct evo_netdesc {
	uint16_t n_in, n_out, n_nodes, n_links;
	uint16_t out_id[EVO_MAX_SKILL_IO];
	evo_netdesc_node node[EVO_NET_MAX_NODES];
	evo_netdesc_link link[EVO_NET_MAX_LINKS];
} evo_netdesc;

/* The .net text format (docs/formats.md):
 *     inputs:N
 *     outputs:M
 *     node:ID:ACTIVATION:BIAS     (every non-input node)
 *     output:ID                   (M lines, in output order)
 *     link:FROM:TO:WEIGHT
 * Numbers are decimal ("-1.25", "3e-2" is not accepted); they are
 * converted to Q16 exactly, rounding to nearest. Ids are 0..65535; links
 * must join existing nodes, never end at an input, and not repeat. */
evo_status evo_netdesc_parse(const char *buf, size_t len, const char *file,
			     evo_netdesc *out, evo_diag *err);

#endif
