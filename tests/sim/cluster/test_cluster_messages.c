/* What rank 0 checks of the messages a rank sends
 * (sim/cluster/cluster_messages.c): a HELLO of another size, status,
 * thread count (-1 divided by zero in rank 0) or task settings, and a
 * RESULT of another size, status, chunk or with a result no evaluation
 * gives, are refused with the rank named; a rank's own message reaches
 * the user with its control bytes made harmless. (Under mpirun, with a
 * rank that sends such a HELLO: test_cluster.c.) */
#include <stdio.h>
#include <string.h>

#include "cluster/cluster_messages.h"
#include "harness.h"
#include "support/doc_block.h"

static const evo_cluster_task TASK = {
    .seed = 11, .reps = 2, .ticks = 60, .n_in = 10, .n_out = 2};

/* A hello as a rank running TASK on 2 threads sends it. */
static evo_cluster_hello good_hello(void)
{
	evo_cluster_hello h;
	memset(&h, 0, sizeof h);
	h.ok = 1;
	h.threads = 2;
	h.reps = 2;
	h.ticks = 60;
	h.seed = 11;
	h.n_in = 10;
	h.n_out = 2;
	snprintf(h.host, sizeof h.host, "node7");
	return h;
}

TEST(a_hello_as_evo_sends_it_is_taken)
{
	evo_cluster_hello h = good_hello(), out;
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_cluster_check_hello(&h, sizeof h, 3, &TASK, &out,
					     &err),
		     0);
	CHECK_EQ_INT(out.threads, 2);
	CHECK_EQ_STR(out.host, "node7");
	/* the most threads a rank may have */
	h.threads = EVO_EVAL_MAX_THREADS;
	CHECK_EQ_INT(evo_cluster_check_hello(&h, sizeof h, 3, &TASK, &out,
					     &err),
		     0);
}

TEST(a_hello_with_threads_no_rank_has_is_refused_naming_the_rank)
{
	static const int32_t bad[] = {-1, 0, EVO_EVAL_MAX_THREADS + 1,
				      2147483647, -2147483647 - 1};
	for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
		evo_cluster_hello h = good_hello(), out;
		h.threads = bad[k];
		evo_err err = {{0}};
		CHECK_EQ_INT(evo_cluster_check_hello(&h, sizeof h, 3, &TASK,
						     &out, &err),
			     -1);
		char want[96];
		snprintf(want, sizeof want,
			 "rank 3 (on node7): a hello with %d threads (a rank "
			 "has 1 to 1024)",
			 (int)bad[k]);
		CHECK_CONTAINS(err.msg, want);
	}
}

/* docs/cluster.md quotes the message of rank 1 on node7 saying -1 threads */
TEST(docs_cluster_md_quotes_the_message_evo_gives)
{
	evo_cluster_hello h = good_hello(), out;
	h.threads = -1;
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_cluster_check_hello(&h, sizeof h, 1, &TASK, &out, &err), -1);
	char doc[2048], want[2048];
	CHECK_EQ_INT(doc_block("docs/cluster.md",
			       "tests/sim/cluster/test_cluster_messages.c", 0, doc,
			       sizeof doc),
		     0);
	snprintf(want, sizeof want, "%s\n", err.msg);
	CHECK_EQ_STR(doc, want);
}

TEST(a_hello_not_evos_is_refused_naming_the_rank)
{
	evo_cluster_hello h = good_hello(), out;
	evo_err err = {{0}};
	/* another size: another evo, or no evo */
	CHECK_EQ_INT(evo_cluster_check_hello(&h, 8, 2, &TASK, &out, &err), -1);
	char want[96];
	snprintf(want, sizeof want, "rank 2: a hello of 8 bytes, where evo's "
				    "has %zu",
		 sizeof h);
	CHECK_CONTAINS(err.msg, want);
	/* a status that is neither up nor down */
	h.ok = 7;
	CHECK_EQ_INT(evo_cluster_check_hello(&h, sizeof h, 2, &TASK, &out,
					     &err),
		     -1);
	CHECK_CONTAINS(err.msg, "rank 2 (on node7): a hello whose status is 7");
	/* other settings: each field */
	for (int f = 0; f < 5; f++) {
		h = good_hello();
		if (f == 0)
			h.seed = 12;
		if (f == 1)
			h.reps = -1;
		if (f == 2)
			h.ticks = -60;
		if (f == 3)
			h.n_in = 4000000000u;
		if (f == 4)
			h.n_out = 3;
		CHECK_EQ_INT(evo_cluster_check_hello(&h, sizeof h, 2, &TASK,
						     &out, &err),
			     -1);
		CHECK_CONTAINS(err.msg, "rank 2 (on node7) runs the task with");
		CHECK_CONTAINS(err.msg, "rank 0 with seed 11, 2 of 60, 10 and 2");
	}
	/* a host and a message without their NUL, with a terminal's escape
	 * sequence: ended, and the control bytes shown as '?' */
	h = good_hello();
	h.ok = 0;
	memset(h.host, 'h', sizeof h.host);
	memset(h.msg, 'm', sizeof h.msg);
	memcpy(h.msg, "\033]0;owned\007", 10);
	CHECK_EQ_INT(evo_cluster_check_hello(&h, sizeof h, 2, &TASK, &out,
					     &err),
		     -1);
	CHECK_CONTAINS(err.msg, "rank 2 (on hhhhhhhh");
	CHECK_CONTAINS(err.msg, "?]0;owned?mmm");
	CHECK(strchr(err.msg, '\033') == NULL);
	CHECK_EQ_INT(strlen(out.host), sizeof out.host - 1);
}

/* A RESULT for the chunk of candidates 4..5: head, then two results. */
static size_t result_msg(unsigned char *buf, int32_t first, int32_t count,
			 int32_t status, const evo_eval_result *r, int n)
{
	int32_t head[3] = {first, count, status};
	memcpy(buf, head, sizeof head);
	memcpy(buf + sizeof head, r, (size_t)n * sizeof *r);
	return sizeof head + (size_t)n * sizeof *r;
}

TEST(a_result_as_evo_sends_it_is_taken)
{
	evo_eval_result r[2], out[2];
	memset(r, 0, sizeof r);
	r[0].fitness = 1.5;
	r[1].fitness = -2;
	r[1].collisions = 30;
	r[1].solved = 1;
	unsigned char buf[sizeof r + 12];
	size_t n = result_msg(buf, 4, 2, 0, r, 2);
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_cluster_check_result(buf, n, 1, "node7", 4, 2, out,
					      &err),
		     0);
	CHECK(out[0].fitness == 1.5 && out[1].fitness == -2 &&
	      out[1].collisions == 30 && out[1].solved == 1);
}

TEST(a_result_not_evos_is_refused_naming_the_rank)
{
	evo_eval_result r[2], out[2];
	memset(r, 0, sizeof r);
	unsigned char buf[sizeof r + 12] = {0};
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_cluster_check_result(buf, 11, 1, "node7", 4, 2, out,
					      &err),
		     -1);
	CHECK_CONTAINS(err.msg, "rank 1 (on node7): a result of 11 bytes");
	size_t n = result_msg(buf, 4, 2, -1, r, 2);
	CHECK_EQ_INT(evo_cluster_check_result(buf, n, 1, "node7", 4, 2, out,
					      &err),
		     -1);
	CHECK_CONTAINS(err.msg,
		       "rank 1 (on node7): a result whose status is -1");
	/* other candidates, another count, fewer bytes than the count */
	n = result_msg(buf, 5, 2, 0, r, 2);
	CHECK_EQ_INT(evo_cluster_check_result(buf, n, 1, "node7", 4, 2, out,
					      &err),
		     -1);
	CHECK_CONTAINS(err.msg, "rank 1 (on node7): results of candidates 5..");
	n = result_msg(buf, 4, 2147483647, 0, r, 2);
	CHECK_EQ_INT(evo_cluster_check_result(buf, n, 1, "node7", 4, 2, out,
					      &err),
		     -1);
	CHECK_CONTAINS(err.msg, "for 4.. (2)");
	n = result_msg(buf, 4, 2, 0, r, 1);
	CHECK_EQ_INT(evo_cluster_check_result(buf, n, 1, "node7", 4, 2, out,
					      &err),
		     -1);
	CHECK_CONTAINS(err.msg, "for 4.. (2)");
	/* a result no evaluation gives */
	for (int f = 0; f < 4; f++) {
		memset(r, 0, sizeof r);
		if (f == 0)
			r[1].solved = 2;
		if (f == 1)
			r[1].collisions = -1;
		if (f == 2)
			r[1].group = 3;
		if (f == 3)
			r[1].wins = -5;
		n = result_msg(buf, 4, 2, 0, r, 2);
		CHECK_EQ_INT(evo_cluster_check_result(buf, n, 1, "node7", 4, 2,
						      out, &err),
			     -1);
		CHECK_CONTAINS(err.msg, "rank 1 (on node7): candidate 5: a "
					"result no evaluation gives");
	}
	/* the rank's own failure, with control bytes and no NUL */
	memset(buf, 'x', sizeof buf);
	int32_t head[3] = {4, 2, 1};
	memcpy(buf, head, sizeof head);
	memcpy(buf + 12, "boom\033[2J", 8);
	CHECK_EQ_INT(evo_cluster_check_result(buf, sizeof buf, 1, "node7", 4,
					      2, out, &err),
		     -1);
	CHECK_CONTAINS(err.msg, "rank 1 (on node7): boom?[2Jxxx");
	CHECK(strchr(err.msg, '\033') == NULL);
}

int main(void)
{
	RUN(a_hello_as_evo_sends_it_is_taken);
	RUN(a_hello_with_threads_no_rank_has_is_refused_naming_the_rank);
	RUN(docs_cluster_md_quotes_the_message_evo_gives);
	RUN(a_hello_not_evos_is_refused_naming_the_rank);
	RUN(a_result_as_evo_sends_it_is_taken);
	RUN(a_result_not_evos_is_refused_naming_the_rank);
	return test_summary();
}
