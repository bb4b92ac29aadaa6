/* The literature tasks (literature.h): XOR and double-pole balancing. The
 * physics follows the NEAT/ESP double-pole code (CartPole::step and rk4),
 * which writes Wieland's equations with g = -9.8. */
#define _POSIX_C_SOURCE 200809L
#include "learn/literature.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define FORCE_MAG   10.0
#define TAU	    0.01 /* RK4 step, s */
#define RK4_PER_ACT 2	 /* a force every 0.02 s */
#define GRAVITY	    (-9.8)
#define MASSCART    1.0
#define MASSPOLE_1  0.1
#define MASSPOLE_2  0.01
#define LENGTH_1    0.5 /* half-lengths, m */
#define LENGTH_2    0.05
#define MUP	    0.000002 /* pole hinge friction */
#define MUC_GOMEZ   0.0005   /* cart-track friction, GOMEZ protocol */
#define TRACK_HALF  2.4
#define PI	    3.14159265358979323846
#define FAIL_ANGLE  (36.0 * PI / 180.0)

/* A compiled network and its memory; the compile scratch is large, so all
 * of it lives on the heap, one per evaluation call. */
typedef struct lit_net {
	evo_net_compile_ws ws;
	evo_net_node nodes[EVO_NET_MAX_NODES];
	evo_net_link links[EVO_NET_MAX_LINKS];
	uint16_t out[EVO_MAX_SKILL_IO];
	evo_q16 act[EVO_NET_MAX_NODES + EVO_MAX_SKILL_IO];
	evo_net net;
} lit_net;

static lit_net *net_open(const evo_netdesc *d, unsigned n_in, evo_err *err)
{
	if (d->n_in != n_in || d->n_out != 1) {
		evo_fail(err,
			 "the network has %u inputs and %u outputs; the task "
			 "needs %u and 1",
			 (unsigned)d->n_in, (unsigned)d->n_out, n_in);
		return NULL;
	}
	lit_net *n = malloc(sizeof *n);
	if (!n) {
		evo_fail(err, "out of memory");
		return NULL;
	}
	evo_status st =
	    evo_net_compile(d, &n->ws, n->nodes, n->links, n->out, &n->net);
	if (st != EVO_OK) {
		evo_fail(err, "the network does not compile: %s",
			 evo_status_str(st));
		free(n);
		return NULL;
	}
	return n;
}

static void net_reset(lit_net *n)
{
	memset(n->act, 0, sizeof n->act);
}

static double net_eval(lit_net *n, const double *in)
{
	evo_q16 qin[EVO_MAX_SKILL_IO], qout[1];
	for (unsigned i = 0; i < n->net.n_in; i++)
		qin[i] = evo_q16_from_double(in[i]);
	evo_net_eval(&n->net, n->act, qin, qout);
	return evo_q16_to_double(qout[0]);
}

/* What a protocol sets: the long pole's start angle and the cart's
 * friction. */
static const struct {
	const char *name;
	double start_th1; /* rad */
	double muc;
} protocols[] = {
    [EVO_LIT_PROTO_NEAT] = {"NEAT", PI / 180.0, 0},
    [EVO_LIT_PROTO_GOMEZ] = {"GOMEZ", 4.0 * PI / 180.0, MUC_GOMEZ},
};

static int same_word(const char *a, const char *upper)
{
	while (*a && toupper((unsigned char)*a) == *upper)
		a++, upper++;
	return !*a && !*upper;
}

int evo_lit_protocol_named(const char *value)
{
	if (!value)
		return EVO_LIT_PROTO_NEAT;
	for (int k = 0; k < (int)(sizeof protocols / sizeof protocols[0]); k++)
		if (same_word(value, protocols[k].name))
			return k;
	return -1;
}

const char *evo_lit_protocol_name(evo_lit_protocol pr)
{
	return protocols[pr].name;
}

evo_lit_task evo_lit_task_named(const char *env)
{
	static const struct {
		const char *name;
		evo_lit_task t;
	} names[] = {
	    {"XOR", EVO_LIT_XOR}, {"DPV", EVO_LIT_DPV}, {"DPNV", EVO_LIT_DPNV}};
	if (!env)
		return EVO_LIT_NONE;
	for (size_t k = 0; k < sizeof names / sizeof names[0]; k++)
		if (same_word(env, names[k].name))
			return names[k].t;
	return EVO_LIT_NONE;
}

unsigned evo_lit_n_in(evo_lit_task t)
{
	return t == EVO_LIT_XOR ? 2 : t == EVO_LIT_DPV ? 6 : 3;
}

int evo_lit_xor(const evo_netdesc *d, evo_lit_result *r, evo_err *err)
{
	static const double in[4][2] = {{0, 0}, {0, 1}, {1, 0}, {1, 1}};
	static const double want[4] = {0, 1, 1, 0};
	lit_net *n = net_open(d, 2, err);
	if (!n)
		return -1;
	double errsum = 0;
	int right = 0;
	for (int k = 0; k < 4; k++) {
		net_reset(n);
		double o = net_eval(n, in[k]);
		errsum += fabs(want[k] - o);
		right += want[k] > 0.5 ? o >= 0.5 : o < 0.5;
	}
	free(n);
	*r = (evo_lit_result){.fitness = (4 - errsum) * (4 - errsum),
			      .steps = 4,
			      .solved = right == 4,
			      .generalisation = -1};
	return 0;
}

evo_lit_pole_state evo_lit_pole_start_for(evo_lit_protocol pr)
{
	return (evo_lit_pole_state){{0, 0, protocols[pr].start_th1, 0, 0, 0}};
}

evo_lit_pole_state evo_lit_pole_start(void)
{
	return evo_lit_pole_start_for(EVO_LIT_PROTO_NEAT);
}

/* ds/dt at s (CartPole::step of the NEAT code), with Wieland's cart
 * friction -muc sgn(xdot) when muc is not 0; a cart at rest feels none. */
static void derivs(const double *s, double force, double muc, double *ds)
{
	if (muc != 0 && s[1] != 0)
		force -= s[1] > 0 ? muc : -muc;
	double c1 = cos(s[2]), s1 = sin(s[2]);
	double c2 = cos(s[4]), s2 = sin(s[4]);
	double ml1 = LENGTH_1 * MASSPOLE_1, ml2 = LENGTH_2 * MASSPOLE_2;
	double t1 = MUP * s[3] / ml1, t2 = MUP * s[5] / ml2;
	double fi1 = ml1 * s[3] * s[3] * s1 +
		     0.75 * MASSPOLE_1 * c1 * (t1 + GRAVITY * s1);
	double fi2 = ml2 * s[5] * s[5] * s2 +
		     0.75 * MASSPOLE_2 * c2 * (t2 + GRAVITY * s2);
	double mi1 = MASSPOLE_1 * (1 - 0.75 * c1 * c1);
	double mi2 = MASSPOLE_2 * (1 - 0.75 * c2 * c2);
	double xacc = (force + fi1 + fi2) / (mi1 + mi2 + MASSCART);
	ds[0] = s[1];
	ds[1] = xacc;
	ds[2] = s[3];
	ds[3] = -0.75 * (xacc * c1 + GRAVITY * s1 + t1) / LENGTH_1;
	ds[4] = s[5];
	ds[5] = -0.75 * (xacc * c2 + GRAVITY * s2 + t2) / LENGTH_2;
}

void evo_lit_pole_rk4_for(evo_lit_protocol pr, evo_lit_pole_state *p,
			  double force, double dt)
{
	double k1[6], k2[6], k3[6], k4[6], y[6];
	double *s = p->s, muc = protocols[pr].muc;
	derivs(s, force, muc, k1);
	for (int i = 0; i < 6; i++)
		y[i] = s[i] + 0.5 * dt * k1[i];
	derivs(y, force, muc, k2);
	for (int i = 0; i < 6; i++)
		y[i] = s[i] + 0.5 * dt * k2[i];
	derivs(y, force, muc, k3);
	for (int i = 0; i < 6; i++)
		y[i] = s[i] + dt * k3[i];
	derivs(y, force, muc, k4);
	for (int i = 0; i < 6; i++)
		s[i] += dt / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
}

void evo_lit_pole_rk4(evo_lit_pole_state *p, double force, double dt)
{
	evo_lit_pole_rk4_for(EVO_LIT_PROTO_NEAT, p, force, dt);
}

int evo_lit_pole_failed(const evo_lit_pole_state *p)
{
	const double *s = p->s;
	return fabs(s[0]) > TRACK_HALF || fabs(s[2]) > FAIL_ANGLE ||
	       fabs(s[4]) > FAIL_ANGLE;
}

/* Balance on an open network; the run behind evo_lit_pole. */
static void balance(evo_lit_protocol pr, lit_net *n, int velocities,
		    const evo_lit_pole_state *start, long max_steps,
		    evo_lit_result *r)
{
	evo_lit_pole_state p = start ? *start : evo_lit_pole_start_for(pr);
	/* Gruau's damping term: the last 100 steps' sums, as a ring. */
	double jiggle[100] = {0};
	long t = 0;
	net_reset(n);
	while (t < max_steps) {
		const double *s = p.s;
		double in[6];
		if (velocities) {
			in[0] = s[0] / 4.8;
			in[1] = s[1] / 2;
			in[2] = s[2] / 0.52;
			in[3] = s[3] / 2;
			in[4] = s[4] / 0.52;
			in[5] = s[5] / 2;
		} else {
			in[0] = s[0] / 4.8;
			in[1] = s[2] / 0.52;
			in[2] = s[4] / 0.52;
		}
		double force = (net_eval(n, in) - 0.5) * 2 * FORCE_MAG;
		force = force > FORCE_MAG    ? FORCE_MAG
			: force < -FORCE_MAG ? -FORCE_MAG
					     : force;
		for (int k = 0; k < RK4_PER_ACT; k++)
			evo_lit_pole_rk4_for(pr, &p, force, TAU);
		if (evo_lit_pole_failed(&p))
			break;
		jiggle[t % 100] =
		    fabs(s[0]) + fabs(s[1]) + fabs(s[2]) + fabs(s[3]);
		t++;
	}
	r->steps = t;
	r->solved = t >= EVO_LIT_POLE_SUCCESS;
	r->generalisation = -1;
	if (velocities) {
		r->fitness = (double)t;
	} else {
		double f2 = 0;
		if (t >= 100) {
			double sum = 0;
			for (int k = 0; k < 100; k++)
				sum += jiggle[k];
			f2 = sum > 0 ? 0.75 / sum : 0;
		}
		r->fitness = 0.1 * (double)t / 1000.0 + 0.9 * f2;
	}
}

int evo_lit_pole_for(evo_lit_protocol pr, const evo_netdesc *d,
		     int velocities, const evo_lit_pole_state *start,
		     long max_steps, evo_lit_result *r, evo_err *err)
{
	lit_net *n = net_open(d, velocities ? 6 : 3, err);
	if (!n)
		return -1;
	balance(pr, n, velocities, start, max_steps, r);
	free(n);
	return 0;
}

int evo_lit_pole(const evo_netdesc *d, int velocities,
		 const evo_lit_pole_state *start, long max_steps,
		 evo_lit_result *r, evo_err *err)
{
	return evo_lit_pole_for(EVO_LIT_PROTO_NEAT, d, velocities, start,
				max_steps, r, err);
}

static int generalise(evo_lit_protocol pr, lit_net *n, int velocities)
{
	static const double frac[5] = {0.05, 0.25, 0.5, 0.75, 0.95};
	int count = 0;
	for (int a = 0; a < 5; a++)
		for (int b = 0; b < 5; b++)
			for (int c = 0; c < 5; c++)
				for (int e = 0; e < 5; e++) {
					evo_lit_pole_state p = {{
					    frac[a] * 4.32 - 2.16,
					    frac[b] * 2.70 - 1.35,
					    frac[c] * 0.12566304 - 0.06283152,
					    frac[e] * 0.30019504 - 0.15009752,
					    0,
					    0,
					}};
					evo_lit_result r;
					balance(pr, n, velocities, &p,
						EVO_LIT_GENERAL_STEPS, &r);
					count +=
					    r.steps >= EVO_LIT_GENERAL_STEPS;
				}
	return count;
}

int evo_lit_generalisation_for(evo_lit_protocol pr, const evo_netdesc *d,
			       int velocities, evo_err *err)
{
	lit_net *n = net_open(d, velocities ? 6 : 3, err);
	if (!n)
		return -1;
	int count = generalise(pr, n, velocities);
	free(n);
	return count;
}

int evo_lit_generalisation(const evo_netdesc *d, int velocities, evo_err *err)
{
	return evo_lit_generalisation_for(EVO_LIT_PROTO_NEAT, d, velocities,
					  err);
}

int evo_lit_dpnv_check_for(evo_lit_protocol pr, const evo_netdesc *d,
			   evo_lit_result *r, evo_err *err)
{
	lit_net *n = net_open(d, 3, err);
	if (!n)
		return -1;
	evo_lit_result run;
	balance(pr, n, 0, NULL, EVO_LIT_POLE_SUCCESS, &run);
	r->generalisation = run.solved ? generalise(pr, n, 0) : -1;
	r->solved = run.solved && r->generalisation >= EVO_LIT_GENERAL_NEEDED;
	free(n);
	return 0;
}

int evo_lit_dpnv_check(const evo_netdesc *d, evo_lit_result *r, evo_err *err)
{
	return evo_lit_dpnv_check_for(EVO_LIT_PROTO_NEAT, d, r, err);
}

int evo_lit_evaluate(evo_lit_task t, evo_lit_protocol pr,
		     const evo_netdesc *d, evo_lit_result *r, evo_err *err)
{
	switch (t) {
	case EVO_LIT_XOR:
		return evo_lit_xor(d, r, err);
	case EVO_LIT_DPV:
		return evo_lit_pole_for(pr, d, 1, NULL, EVO_LIT_POLE_SUCCESS,
					r, err);
	case EVO_LIT_DPNV:
		if (evo_lit_pole_for(pr, d, 0, NULL, EVO_LIT_DAMPING_STEPS, r,
				     err))
			return -1;
		r->solved = 0;
		return 0;
	default:
		return evo_fail(err, "not a literature task");
	}
}
