/* The text of a docs block a test checks: the fenced block after the line
 * `<!-- checked by TEST -->` in a .md file (tests/test_docs.sh fails on a
 * docs block that nothing checks, and takes this mark only from a test
 * that holds it). Run from the repository root, as make test does. */
#ifndef EVO_TESTS_DOC_BLOCK_H
#define EVO_TESTS_DOC_BLOCK_H

#include <stdio.h>
#include <string.h>

/* The block of `doc` marked as checked by `test` into out (its lines, each
 * ending in '\n'); 0, or -1 when the file, the mark or the block is
 * missing or the block does not fit. */
static inline int doc_block(const char *doc, const char *test, char *out, size_t size)
{
	char mark[256], line[4096];
	snprintf(mark, sizeof mark, "<!-- checked by %s -->", test);
	FILE *fp = fopen(doc, "r");
	int state = 0; /* 0 looking, 1 after the mark, 2 in the block */
	size_t n = 0;
	if (!fp)
		return -1;
	out[0] = 0;
	while (state < 3 && fgets(line, sizeof line, fp)) {
		size_t len = strlen(line);
		if (state == 0 && strncmp(line, mark, strlen(mark)) == 0 &&
		    line[strlen(mark)] == '\n')
			state = 1;
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

#endif
