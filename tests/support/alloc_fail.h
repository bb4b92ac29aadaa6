/* Allocation failure on demand, for tests of code that must survive it
 * with a message instead of a crash. Every test binary links this file's
 * strdup in place of the C library's; it copies as strdup does until a
 * test arms it, and then fails (NULL, errno ENOMEM) at the call asked
 * for. Safe to call from several threads. */
#ifndef EVO_TEST_ALLOC_FAIL_H
#define EVO_TEST_ALLOC_FAIL_H

/* From now on, the nth call to strdup fails (1: the next one); 0 disarms.
 * Resets the count of calls. */
void alloc_fail_strdup(int nth);

/* Calls to strdup since the last alloc_fail_strdup. */
int alloc_fail_strdup_calls(void);

#endif
