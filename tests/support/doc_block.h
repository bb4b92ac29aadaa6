/* The text of a docs block a test checks: a fenced block after the line
 * `<!-- checked by TEST -->` in a .md file (tests/test_docs.sh fails on a
 * docs block that nothing checks, and takes this mark only from a test
 * that holds it), and whether its lines are lines a run printed. Run from
 * the repository root, as make test does. */
#ifndef EVO_TESTS_DOC_BLOCK_H
#define EVO_TESTS_DOC_BLOCK_H

#include <ctype.h>
#include <stdio.h>
#include <string.h>

/* Block `nth` (0 the first) of `doc` marked as checked by `test` into out
 * (its lines, each ending in '\n'); 0, or -1 when the file, the mark or
 * the block is missing or the block does not fit. */
static inline int doc_block(const char *doc, const char *test, int nth, char *out,
			    size_t size)
{
	char mark[256], line[4096];
	snprintf(mark, sizeof mark, "<!-- checked by %s -->\n", test);
	FILE *fp = fopen(doc, "r");
	int state = 0; /* 0 looking, 1 after the mark, 2 in the block */
	size_t n = 0;
	if (!fp)
		return -1;
	out[0] = 0;
	while (state < 3 && fgets(line, sizeof line, fp)) {
		size_t len = strlen(line);
		if (state == 0 && strcmp(line, mark) == 0)
			state = nth-- > 0 ? 0 : 1;
		else if (state >= 1 && strncmp(line, "```", 3) == 0)
			state++;
		else if (state == 2) {
			if (n + len + 1 > size) {
				fclose(fp);
				return -1;
			}
			memcpy(out + n, line, len + 1);
			n += len;
		}
	}
	fclose(fp);
	return state == 3 ? 0 : -1;
}

/* Whether the docs line a (up to its '\n') matches the printed line b (up
 * to its '\n'): "..." in a stands for any text (what the docs leave
 * out); with any_number, a run of digits in a for any run of digits (what
 * varies from run to run: sessions, counts, ports) and a run of spaces
 * for any run of spaces (a column's padding). */
static inline int doc_line_matches(const char *a, const char *b, int any_number)
{
	while (*a && *a != '\n') {
		if (strncmp(a, "...", 3) == 0) {
			for (const char *k = b;; k++) {
				if (doc_line_matches(a + 3, k, any_number))
					return 1;
				if (!*k || *k == '\n')
					return 0;
			}
		}
		if (!*b || *b == '\n')
			return 0;
		if (any_number && isdigit((unsigned char)*a) &&
		    isdigit((unsigned char)*b)) {
			while (isdigit((unsigned char)*a))
				a++;
			while (isdigit((unsigned char)*b))
				b++;
		} else if (any_number && *a == ' ' && *b == ' ') {
			while (*a == ' ')
				a++;
			while (*b == ' ')
				b++;
		} else if (*a == *b) {
			a++;
			b++;
		} else
			return 0;
	}
	return !*b || *b == '\n';
}

/* Whether `line` matches a whole line of `out` (doc_line_matches). */
static inline int doc_line_printed(const char *line, const char *out, int any_number)
{
	for (const char *o = out; *o; o = strchr(o, '\n') ? strchr(o, '\n') + 1 : "")
		if (doc_line_matches(line, o, any_number))
			return 1;
	return 0;
}

/* How many lines of `block` are not lines of `out`, once each subst[2k]
 * in them is subst[2k + 1] (the names a test gave what the docs call
 * otherwise; subst ends with NULL, or is NULL); each such line is said on
 * stderr. */
static inline int doc_lines_missing(const char *block, const char *out,
				    const char *const *subst, int any_number)
{
	int missing = 0;
	char line[4096];
	for (const char *l = block; *l; l = strchr(l, '\n') ? strchr(l, '\n') + 1 : "") {
		size_t n = 0;
		for (const char *c = l; *c && *c != '\n' && n + 1 < sizeof line;) {
			const char *const *s = subst;
			while (s && *s && strncmp(c, s[0], strlen(s[0])) != 0)
				s += 2;
			if (s && *s && n + strlen(s[1]) + 1 < sizeof line) {
				memcpy(line + n, s[1], strlen(s[1]));
				n += strlen(s[1]);
				c += strlen(s[0]);
			} else
				line[n++] = *c++;
		}
		line[n] = 0;
		if (n > 0 && !doc_line_printed(line, out, any_number)) {
			fprintf(stderr, "  docs line not printed: %s\n", line);
			missing++;
		}
	}
	return missing;
}

#endif
