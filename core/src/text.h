/* Private helpers of the text-format parsers: strings without <string.h>,
 * a small message formatter, the entry lexer every format shares, and edit
 * distance for "did you mean" hints. Prefix txt_. */
#ifndef EVO_TEXT_H
#define EVO_TEXT_H

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include "evo/formats.h"

/* A piece of the input buffer: not NUL-terminated, may hold any byte. */
typedef struct txt_slice {
	const char *s;
	size_t len;
} txt_slice;

size_t txt_len(const char *s);
/* 1 when equal; the _i versions ignore ASCII case. */
int txt_eq(const char *a, const char *b);
int txt_ieq(const char *a, const char *b);
int txt_slice_ieq(txt_slice a, const char *b);
int txt_slice_eq(txt_slice a, const char *b);
/* ASCII upper case of c. */
char txt_upper(char c);

/* Copies s into dst (cap bytes), NUL-terminates, and zero-fills the rest
 * so a parsed struct has no stray bytes (mind images hash names). Returns
 * 0, or -1 when s did not fit (dst then holds a truncated copy). */
int txt_copy(char *dst, size_t cap, txt_slice s);

/* A tiny snprintf into dst, always NUL-terminated; returns the length
 * written. Conversions: %s (C string), %d (int), %u (unsigned), %c, %%,
 * and %.*s (int length, const char *) for a slice of the input: bytes
 * that are not printable show as '?', and a slice longer than
 * TXT_QUOTE_MAX bytes is cut and ends in "...", so a message never
 * drowns in a huge line. */
#define TXT_QUOTE_MAX 60
/* The two arguments of %.*s for a slice, safe for any length. */
#define TXT_Q(sl)                                                              \
	(int)((sl).len > TXT_QUOTE_MAX ? TXT_QUOTE_MAX + 1 : (sl).len), (sl).s
size_t txt_vfmt(char *dst, size_t cap, const char *fmt, va_list ap);
size_t txt_fmt(char *dst, size_t cap, const char *fmt, ...);

/* Fills d with "file:line: " and the formatted text; d may be NULL. */
void txt_diag(evo_diag *d, const char *file, uint32_t line, const char *fmt,
	      ...);

/* ---- the entry lexer ---------------------------------------------- */

/* Fields beyond this many are counted but not kept; txt_rest reaches
 * them. No format needs more than four. */
#define TXT_MAX_FIELDS 6

/* An entry: words joined by ':', with the blanks around each ':' trimmed
 * from the fields (text keeps them). */
typedef struct txt_entry {
	txt_slice text;
	uint32_t line;
	size_t n_fields; /* 1 + the number of ':' */
	txt_slice field[TXT_MAX_FIELDS];
} txt_entry;

typedef struct txt_lexer {
	const char *buf;
	size_t len, pos;
	uint32_t line;
	int line_start; /* nothing but blanks seen yet on this line */
	const char *file;
} txt_lexer;

void txt_lex_init(txt_lexer *lx, const char *buf, size_t len, const char *file);

/* The next entry: 1 with *e filled, 0 at the end of the input, or -1
 * with err filled when a control byte (NUL, ...) stands outside a
 * comment. */
int txt_lex_next(txt_lexer *lx, txt_entry *e, evo_diag *err);

/* The line to blame for something missing at the end: the last line. */
uint32_t txt_lex_end_line(const txt_lexer *lx);

/* Everything from field i to the end of the entry, ':' included. */
txt_slice txt_rest(const txt_entry *e, size_t i);

/* ---- numbers and names -------------------------------------------- */

/* Parses s as a whole number 0..max (digits only, no sign). Returns 0,
 * -1 when s is not a whole number, -2 when it is larger than max. */
int txt_uint(txt_slice s, uint32_t max, uint32_t *out);

/* Levenshtein distance between s and b, ignoring ASCII case; inputs
 * longer than EVO_NAME_MAX count only their first EVO_NAME_MAX bytes. */
unsigned txt_distance(txt_slice s, const char *b);

/* The entry of list (n names, or NULL-terminated when n is 0) closest to
 * s by txt_distance; the first wins a tie. */
const char *txt_closest(txt_slice s, const char *const *list, size_t n);

/* Copies field f of entry e into dst (EVO_NAME_MAX bytes) as a name:
 * EVO_ERR_SYNTAX when it is empty, EVO_ERR_LIMIT when too long, both with
 * err filled. what says which name, with its article ("a sensor name"). */
evo_status txt_name(char *dst, txt_slice f, const txt_entry *e,
		    const char *what, const char *file, evo_diag *err);

#endif
