/* Private helpers of the text-format parsers: strings without <string.h>,
 * a small message formatter, the entry lexer every format shares, and edit
 * distance for "did you mean" hints. Prefix evo_txt_. */
#ifndef EVO_TEXT_H
#define EVO_TEXT_H

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include "evo/formats.h"

/* A piece of the input buffer: not NUL-terminated, may hold any byte. */
typedef struct evo_txt_slice {
	const char *s;
	size_t len;
} evo_txt_slice;

size_t evo_txt_len(const char *s);
/* 1 when equal; the _i versions ignore ASCII case. */
int evo_txt_eq(const char *a, const char *b);
int evo_txt_ieq(const char *a, const char *b);
int evo_txt_slice_ieq(evo_txt_slice a, const char *b);
int evo_txt_slice_eq(evo_txt_slice a, const char *b);
/* ASCII upper case of c. */
char evo_txt_upper(char c);

/* Copies s into dst (cap bytes), NUL-terminates, and zero-fills the rest
 * so a parsed struct has no stray bytes (mind images hash names). Returns
 * 0, or -1 when s did not fit (dst then holds a truncated copy). */
int evo_txt_copy(char *dst, size_t cap, evo_txt_slice s);

/* A tiny snprintf into dst, always NUL-terminated; returns the length
 * written. Conversions: %s (C string), %d (int), %u (unsigned), %c, %%,
 * and %.*s (int length, const char *) for a slice of the input: bytes
 * that are not printable show as '?', and a slice longer than
 * EVO_TXT_QUOTE_MAX bytes is cut and ends in "...", so a message never
 * drowns in a huge line. */
#define EVO_TXT_QUOTE_MAX 60
/* The two arguments of %.*s for a slice, safe for any length. */
#define EVO_TXT_Q(sl)                                                          \
	(int)((sl).len > EVO_TXT_QUOTE_MAX ? EVO_TXT_QUOTE_MAX + 1             \
					   : (sl).len),                        \
	    (sl).s
size_t evo_txt_vfmt(char *dst, size_t cap, const char *fmt, va_list ap);
size_t evo_txt_fmt(char *dst, size_t cap, const char *fmt, ...);

/* Fills d with "file:line: " and the formatted text; d may be NULL. */
void evo_txt_diag(evo_diag *d, const char *file, uint32_t line, const char *fmt,
		  ...);

/* ---- the entry lexer ---------------------------------------------- */

/* Fields beyond this many are counted but not kept; evo_txt_rest reaches
 * them. No format needs more than four. */
#define EVO_TXT_MAX_FIELDS 6

/* An entry: words joined by ':', with the blanks around each ':' trimmed
 * from the fields (text keeps them). */
typedef struct evo_txt_entry {
	evo_txt_slice text;
	uint32_t line;
	size_t n_fields; /* 1 + the number of ':' */
	evo_txt_slice field[EVO_TXT_MAX_FIELDS];
} evo_txt_entry;

typedef struct evo_txt_lexer {
	const char *buf;
	size_t len, pos;
	uint32_t line;
	int line_start; /* nothing but blanks seen yet on this line */
	const char *file;
} evo_txt_lexer;

void evo_txt_lex_init(evo_txt_lexer *lx, const char *buf, size_t len,
		      const char *file);

/* The next entry: 1 with *e filled, 0 at the end of the input, or -1
 * with err filled when a control byte (NUL, ...) stands outside a
 * comment. */
int evo_txt_lex_next(evo_txt_lexer *lx, evo_txt_entry *e, evo_diag *err);

/* The line to blame for something missing at the end: the last line. */
uint32_t evo_txt_lex_end_line(const evo_txt_lexer *lx);

/* Everything from field i to the end of the entry, ':' included. */
evo_txt_slice evo_txt_rest(const evo_txt_entry *e, size_t i);

/* ---- numbers and names -------------------------------------------- */

/* Parses s as a whole number 0..max (digits only, no sign). Returns 0,
 * -1 when s is not a whole number, -2 when it is larger than max. */
int evo_txt_uint(evo_txt_slice s, uint32_t max, uint32_t *out);

/* Levenshtein distance between s and b, ignoring ASCII case; inputs
 * longer than EVO_NAME_MAX count only their first EVO_NAME_MAX bytes. */
unsigned evo_txt_distance(evo_txt_slice s, const char *b);

/* The entry of list (n names, or NULL-terminated when n is 0) closest to
 * s by evo_txt_distance; the first wins a tie. */
const char *evo_txt_closest(evo_txt_slice s, const char *const *list, size_t n);

/* Copies field f of entry e into dst (EVO_NAME_MAX bytes) as a name:
 * EVO_ERR_SYNTAX when it is empty, EVO_ERR_LIMIT when too long, both with
 * err filled. what says which name, with its article ("a sensor name"). */
evo_status evo_txt_name(char *dst, evo_txt_slice f, const evo_txt_entry *e,
			const char *what, const char *file, evo_diag *err);

#endif
