/* evo — the text of printf's "%.17g" for a double, without printf: a
 * checkpoint writes every weight of every genome so (lua_neat.c's dump),
 * and glibc's general conversion cost ~500 instructions a number. */
#ifndef EVO_G17_H
#define EVO_G17_H

#include <stddef.h>

/* Write what snprintf(out, cap, "%.17g", x) writes, for cap >= 32, and
 * return its length. Finite x from 1e-5 to below 1e17 in magnitude is
 * converted with integer arithmetic (exact: the 17 digits are the exact
 * value rounded half to even, as glibc rounds); others go to snprintf. */
size_t evo_g17(double x, char *out, size_t cap);

#endif
