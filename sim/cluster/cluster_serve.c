/* The other ranks' side of a cluster run (sim/cluster/cluster.h): the
 * loop that answers rank 0's chunks with their results, takes an
 * environment genome or a grown hierarchy, and says hello, until rank 0
 * says stop (evo_cluster_serve). */
#define _GNU_SOURCE /* sched_getaffinity */
#include "cluster/cluster.h"

#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cluster/cluster_internal.h"

/* ---- the other ranks ----------------------------------------------------- */

/* Room for k networks and their results; -1 when memory is out. */
static int nets_room(evo_cluster *c, int k)
{
	if (k <= c->n_nets)
		return 0;
	free(c->nets);
	free(c->ptr);
	free(c->res);
	c->nets = malloc((size_t)k * sizeof *c->nets);
	c->ptr = malloc((size_t)k * sizeof *c->ptr);
	c->res = malloc((size_t)k * sizeof *c->res);
	c->n_nets = c->nets && c->ptr && c->res ? k : 0;
	return c->n_nets ? 0 : -1;
}

/* Evaluate a CHUNK of st's length; send its RESULT. */
static void answer_chunk(evo_cluster *c, evo_evaluator *ev, MPI_Status *st)
{
	int len;
	MPI_Get_count(st, MPI_BYTE, &len);
	unsigned char *buf = cluster_room(c, len > 0 ? (size_t)len : 1);
	evo_err e = {{0}};
	int32_t head[3] = {0, 0, 0};
	int rc = 0;
	if (!buf)
		cluster_out_of_memory(c->rank);
	MPI_Recv(buf, len, MPI_BYTE, 0, TAG_CHUNK, MPI_COMM_WORLD,
		 MPI_STATUS_IGNORE);
	if (len < (int)sizeof head)
		rc = evo_fail(&e, "a chunk of %d bytes", len);
	if (!rc) {
		memcpy(head, buf, sizeof head);
		/* a network takes 8 bytes at least: a count the chunk cannot
		 * hold asks for memory it has no use for */
		if (head[0] < 0 || head[1] < 0 || head[2] < 1 ||
		    head[2] > (len - (int)sizeof head) / 8 ||
		    head[1] > INT32_MAX - head[2] || nets_room(c, head[2]))
			rc = evo_fail(&e,
				      "a chunk of %d networks from candidate "
				      "%d of generation %d, in %d bytes",
				      head[2], head[1], head[0], len);
	}
	if (!rc && !ev)
		rc = evo_fail(&e, "no evaluator");
	if (!rc && c->genome_failed) {
		e = c->genome_err;
		rc = -1;
	}
	const unsigned char *p = buf + sizeof head, *end = buf + len;
	for (int i = 0; !rc && i < head[2]; i++) {
		if (cluster_unpack_net(&p, end, &c->nets[i]))
			rc = evo_fail(&e,
				      "candidate %d: a network evo cannot "
				      "read",
				      head[1] + i);
		c->ptr[i] = &c->nets[i];
	}
	if (!rc)
		rc = evo_evaluate_part(ev, c->ptr, head[1], head[2], head[0],
				       c->res, &e);
	int32_t out[3] = {head[1], head[2], rc ? 1 : 0};
	size_t body =
	    rc ? strlen(e.msg) + 1 : (size_t)head[2] * sizeof(evo_eval_result);
	unsigned char *msg = malloc(sizeof out + body);
	if (!msg) {
		out[2] = 1;
		MPI_Send(out, (int)sizeof out, MPI_BYTE, 0, TAG_RESULT,
			 MPI_COMM_WORLD);
		return;
	}
	memcpy(msg, out, sizeof out);
	memcpy(msg + sizeof out,
	       rc ? (const void *)e.msg : (const void *)c->res, body);
	MPI_Send(msg, (int)(sizeof out + body), MPI_BYTE, 0, TAG_RESULT,
		 MPI_COMM_WORLD);
	free(msg);
}

/* A GENOME of st's length: the environment genome of the chunks to
 * come. One that cannot be set fails them, with the reason. */
static void take_genome(evo_cluster *c, evo_evaluator *ev, MPI_Status *st)
{
	int len;
	MPI_Get_count(st, MPI_BYTE, &len);
	unsigned char *buf = cluster_room(c, len > 0 ? (size_t)len : 1);
	if (!buf)
		cluster_out_of_memory(c->rank);
	MPI_Recv(buf, len, MPI_BYTE, 0, TAG_GENOME, MPI_COMM_WORLD,
		 MPI_STATUS_IGNORE);
	c->genome_failed = 0;
	if (len > 0 && buf[len - 1] != 0)
		c->genome_failed = evo_fail(&c->genome_err,
					    "an environment genome of %d "
					    "bytes with no end",
					    len) != 0;
	else if (ev && evo_evaluator_set_genome(ev,
						len > 0 ? (const char *)buf
							: NULL,
						&c->genome_err))
		c->genome_failed = 1;
}

/* Tell rank 0 the settings of ev, made as def says, or (ev NULL) why
 * there is none: err. */
static void say_hello(const evo_evaluator *ev, const evo_eval_def *def,
		      const evo_err *err)
{
	evo_cluster_hello h;
	memset(&h, 0, sizeof h);
	/* the name may be longer than the hello holds */
	char host[MPI_MAX_PROCESSOR_NAME + 1] = "";
	int len = 0;
	MPI_Get_processor_name(host, &len);
	snprintf(h.host, sizeof h.host, "%.63s", host);
	if (ev) {
		h.ok = 1;
		h.threads = evo_evaluator_settings(ev)->threads;
		h.reps = evo_evaluator_settings(ev)->reps;
		h.ticks = evo_evaluator_settings(ev)->ticks;
		h.seed = def->seed;
		h.n_in = evo_evaluator_settings(ev)->n_in;
		h.n_out = evo_evaluator_settings(ev)->n_out;
	} else {
		snprintf(h.msg, sizeof h.msg, "%s", err->msg);
	}
	MPI_Send(&h, (int)sizeof h, MPI_BYTE, 0, TAG_HELLO, MPI_COMM_WORLD);
}

/* The texts ended by a 0 byte in msg[0 .. len-1], which must end with
 * one: their number (0 when msg does not end so). */
static size_t count_texts(const unsigned char *msg, int len)
{
	if (len < 1 || msg[len - 1] != 0)
		return 0;
	size_t n = 0;
	for (int i = 0; i < len; i++)
		n += msg[i] == 0;
	return n;
}

/* A GROW of st's length: ev (destroyed) made anew as it says, with def's
 * threads, seed and ticks; hello again. The new evaluator, or NULL with
 * err set when it could not be made (the hello said why). */
static evo_evaluator *take_grow(evo_cluster *c, evo_evaluator *ev,
				const evo_eval_def *def, MPI_Status *st,
				evo_err *err)
{
	int len;
	MPI_Get_count(st, MPI_BYTE, &len);
	if (!cluster_room(c, len > 0 ? (size_t)len : 1))
		cluster_out_of_memory(c->rank);
	MPI_Recv(c->buf, len, MPI_BYTE, 0, TAG_GROW, MPI_COMM_WORLD,
		 MPI_STATUS_IGNORE);
	evo_evaluator_destroy(ev);
	ev = NULL;
	c->genome_failed = 0;
	evo_err e = {{0}};
	size_t n = count_texts(c->buf, len);
	evo_net_choice *nets =
	    n >= 2 && n % 2 == 0 ? malloc((n / 2) * sizeof *nets) : NULL;
	if (n < 2 || n % 2) {
		evo_fail(&e, "a grown task of %d bytes that is not evo's", len);
	} else if (!nets) {
		evo_fail(&e, "out of memory");
	} else {
		evo_eval_def g = *def;
		const char *p = (const char *)c->buf;
		g.task_path = p;
		p += strlen(p) + 1;
		g.learning_skill = *p ? p : NULL;
		p += strlen(p) + 1;
		g.n_nets = (unsigned)(n / 2 - 1);
		for (unsigned k = 0; k < g.n_nets; k++) {
			nets[k].skill = p;
			p += strlen(p) + 1;
			nets[k].source = p;
			p += strlen(p) + 1;
		}
		g.nets = nets;
		evo_err why = {{0}};
		ev = evo_evaluator_create(&g, &why);
		if (!ev)
			evo_fail(&e,
				 "the hierarchy rank 0 grew does not load "
				 "here (%s); every rank reads it where rank 0 "
				 "wrote it, in the run folder: give --run a "
				 "folder all the machines share",
				 why.msg);
	}
	free(nets);
	say_hello(ev, def, &e);
	if (!ev)
		*err = e;
	return ev;
}

int evo_cluster_serve(evo_cluster *c, const evo_eval_def *def, evo_err *err)
{
	evo_evaluator *ev = evo_evaluator_create(def, err);
	say_hello(ev, def, err);
	for (;;) {
		MPI_Status st;
		cluster_wait_message(0, MPI_ANY_TAG, &st);
		if (st.MPI_TAG == TAG_STOP) {
			MPI_Recv(NULL, 0, MPI_BYTE, 0, TAG_STOP, MPI_COMM_WORLD,
				 MPI_STATUS_IGNORE);
			break;
		}
		if (st.MPI_TAG == TAG_CHUNK) {
			answer_chunk(c, ev, &st);
		} else if (st.MPI_TAG == TAG_GENOME) {
			take_genome(c, ev, &st);
		} else if (st.MPI_TAG == TAG_GROW) {
			ev = take_grow(c, ev, def, &st, err);
		} else { /* not evo's: take it off the queue */
			int n;
			MPI_Get_count(&st, MPI_BYTE, &n);
			unsigned char *buf = cluster_room(c, n > 0 ? (size_t)n : 1);
			if (!buf)
				cluster_out_of_memory(c->rank);
			MPI_Recv(buf, n, MPI_BYTE, 0, st.MPI_TAG,
				 MPI_COMM_WORLD, MPI_STATUS_IGNORE);
		}
	}
	int rc = ev ? 0 : -1;
	evo_evaluator_destroy(ev);
	return rc;
}
