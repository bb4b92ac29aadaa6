/* evo's test harness: a few macros and one runner, no malloc.
 *
 *     TEST(parses_crlf) { CHECK(x == 1); CHECK_EQ_INT(a, b); }
 *     int main(void) { RUN(parses_crlf); return test_summary(); }
 *
 * A test passes when none of its checks fail. test_summary prints
 * "N passed, N failed" as the last line and returns non-zero on failure.
 * Output goes through test_write, which a target without stdio (the
 * firmware under QEMU) can provide by defining TEST_WRITE before including
 * this header. */
#ifndef EVO_TEST_HARNESS_H
#define EVO_TEST_HARNESS_H

#include <stdint.h>
#include <string.h>

#ifndef TEST_WRITE
#include <stdio.h>
#define TEST_WRITE(s) fputs((s), stdout)
#endif

static int test_passed_count, test_failed_count, test_current_failed;
static const char *test_current_name;

static void test_write_uint(unsigned long v)
{
	char buf[24];
	int i = (int)sizeof buf - 1;
	buf[i] = 0;
	do {
		buf[--i] = (char)('0' + v % 10);
		v /= 10;
	} while (v && i > 0);
	TEST_WRITE(buf + i);
}

static void test_write_int(long long v)
{
	if (v < 0) {
		TEST_WRITE("-");
		test_write_uint((unsigned long)(-(v + 1)) + 1);
	} else {
		test_write_uint((unsigned long)v);
	}
}

static void test_fail_at(const char *file, int line, const char *what)
{
	if (!test_current_failed) {
		TEST_WRITE("FAIL ");
		TEST_WRITE(test_current_name ? test_current_name : "?");
		TEST_WRITE("\n");
	}
	test_current_failed = 1;
	TEST_WRITE("  ");
	TEST_WRITE(file);
	TEST_WRITE(":");
	test_write_uint((unsigned long)line);
	TEST_WRITE(": ");
	TEST_WRITE(what);
	TEST_WRITE("\n");
}

#define TEST(name) static void name(void)

#define CHECK(cond)                                                            \
	do {                                                                   \
		if (!(cond))                                                   \
			test_fail_at(__FILE__, __LINE__, "CHECK(" #cond ")");  \
	} while (0)

#define CHECK_EQ_INT(a, b)                                                     \
	do {                                                                   \
		long long test_a_ = (long long)(a), test_b_ = (long long)(b);  \
		if (test_a_ != test_b_) {                                      \
			test_fail_at(__FILE__, __LINE__, #a " == " #b);        \
			TEST_WRITE("    got ");                                \
			test_write_int(test_a_);                               \
			TEST_WRITE(", want ");                                 \
			test_write_int(test_b_);                               \
			TEST_WRITE("\n");                                      \
		}                                                              \
	} while (0)

#define CHECK_EQ_STR(a, b)                                                     \
	do {                                                                   \
		const char *test_a_ = (a), *test_b_ = (b);                     \
		if (!test_a_ || !test_b_ || strcmp(test_a_, test_b_) != 0) {   \
			test_fail_at(__FILE__, __LINE__, #a " == " #b);        \
			TEST_WRITE("    got  \"");                             \
			TEST_WRITE(test_a_ ? test_a_ : "(null)");              \
			TEST_WRITE("\"\n    want \"");                         \
			TEST_WRITE(test_b_ ? test_b_ : "(null)");              \
			TEST_WRITE("\"\n");                                    \
		}                                                              \
	} while (0)

/* a contains b as a substring. */
#define CHECK_CONTAINS(a, b)                                                   \
	do {                                                                   \
		const char *test_a_ = (a), *test_b_ = (b);                     \
		if (!test_a_ || !test_b_ || !strstr(test_a_, test_b_)) {       \
			test_fail_at(__FILE__, __LINE__,                       \
				     #a " contains " #b);                      \
			TEST_WRITE("    got  \"");                             \
			TEST_WRITE(test_a_ ? test_a_ : "(null)");              \
			TEST_WRITE("\"\n    want \"");                         \
			TEST_WRITE(test_b_ ? test_b_ : "(null)");              \
			TEST_WRITE("\"\n");                                    \
		}                                                              \
	} while (0)

#define RUN(name)                                                              \
	do {                                                                   \
		test_current_name = #name;                                     \
		test_current_failed = 0;                                       \
		name();                                                        \
		if (test_current_failed)                                       \
			test_failed_count++;                                   \
		else                                                           \
			test_passed_count++;                                   \
	} while (0)

static int test_summary(void)
{
	test_write_uint((unsigned long)test_passed_count);
	TEST_WRITE(" passed, ");
	test_write_uint((unsigned long)test_failed_count);
	TEST_WRITE(" failed\n");
	return test_failed_count != 0;
}

#endif
