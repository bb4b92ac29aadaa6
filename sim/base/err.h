/* evo — the host side's error message: where and what went wrong, for the
 * user. Every host function that can fail returns -1 (or NULL) and fills
 * one of these; the caller prints it or passes it up. */
#ifndef EVO_ERR_H
#define EVO_ERR_H

/* A message for the user: "file:line: what was expected, what was found". */
typedef struct evo_err {
	char msg[1024];
} evo_err;

/* Fill err (may be NULL) with a printf-style message; returns -1, for
 * `return evo_fail(err, ...)`. */
int evo_fail(evo_err *err, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));

/* A warning for the user, "warning: " and the printf-style message on
 * stderr, counted: evo check ends with how many there were (a misspelt
 * key is a warning, and almost always a mistake). */
void evo_warning(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* How many evo_warning has printed in this process. */
unsigned evo_warning_count(void);

/* on: evo_warning neither prints nor counts until called with 0, which
 * returns how many warnings it swallowed (a task tried quietly). */
unsigned evo_warning_quiet(int on);

#endif
