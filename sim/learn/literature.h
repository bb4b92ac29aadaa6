/* The literature tasks that prove NEAT (Stanley & Miikkulainen 2002,
 * section 4): XOR, and double-pole balancing with velocities (DPV) and
 * without (DPNV), evaluating evo's fixed-point networks (evo/net.h).
 *
 * A LEARNSIM task whose ENV is XOR, DPV or DPNV is evaluated here instead
 * of in a Box2D scene (sim/learn/evaluate.c); docs/learning.md, "Literature
 * tasks", says how each is set up and scored.
 *
 * Double pole (Wieland's equations, as in the NEAT and ESP code): cart
 * 1 kg on a 4.8 m track (|x| <= 2.4 m), poles of half-length 0.5 m and
 * 0.05 m with masses 0.1 and 0.01 kg, g = 9.8 m/s^2, pole hinge friction
 * 2e-6. RK4 at 0.01 s; the network sets a force in [-10, 10] N every
 * 0.02 s (two RK4 steps). The run fails when a pole leans beyond 36
 * degrees or the cart leaves the track.
 *
 * Two protocols (the task's POLEPROTOCOL key) differ in two things only:
 *   NEAT   Stanley & Miikkulainen 2002: long pole started at 1 degree, no
 *          cart friction (as the NEAT code);
 *   GOMEZ  Gomez, Schmidhuber & Miikkulainen 2008 (JMLR 9), tables 3 and
 *          4: long pole started at 4 degrees, cart-track friction 5e-4
 *          (Wieland's -mu_c sgn(xdot) term, sgn(0) = 0).
 * Everything else (inputs, fitness, success, the 625 generalisation
 * starts) is the same in both.
 *
 * Network inputs, scaled as the standard NEAT double-pole code does:
 *   DPV:  x/4.8, xdot/2, th1/0.52, th1dot/2, th2/0.52, th2dot/2
 *   DPNV: x/4.8, th1/0.52, th2/0.52
 * (angles in radians). That code also feeds a constant 0.5 input; evo's
 * networks have a bias per node instead (NEAT's bias node maps onto it),
 * so it is left out. One output o in [0, 1] gives the force
 * (o - 0.5) * 20 N, clamped to [-10, 10]. */
#ifndef EVO_LITERATURE_H
#define EVO_LITERATURE_H

#include "base/err.h"
#include "evo/evo.h"

#define EVO_LIT_POLE_SUCCESS   100000L /* steps that count as balanced */
#define EVO_LIT_DAMPING_STEPS  1000L   /* the DPNV fitness run */
#define EVO_LIT_GENERAL_STEPS  1000L   /* each generalisation start */
#define EVO_LIT_GENERAL_STARTS 625
#define EVO_LIT_GENERAL_NEEDED 200 /* Gruau's bar for a DPNV solution */

typedef enum evo_lit_task {
	EVO_LIT_NONE = 0,
	EVO_LIT_XOR,
	EVO_LIT_DPV,
	EVO_LIT_DPNV
} evo_lit_task;

/* The double-pole protocol: whose start state and friction. */
typedef enum evo_lit_protocol {
	EVO_LIT_PROTO_NEAT = 0, /* the default: every task without the key */
	EVO_LIT_PROTO_GOMEZ
} evo_lit_protocol;

/* The protocol POLEPROTOCOL's value names (case-insensitive "NEAT",
 * "GOMEZ"; NULL: the default, NEAT), or -1 when it names none. */
int evo_lit_protocol_named(const char *value);

/* "NEAT" or "GOMEZ". */
const char *evo_lit_protocol_name(evo_lit_protocol pr);

/* The task an ENV value names (case-insensitive "XOR", "DPV", "DPNV"),
 * or EVO_LIT_NONE. */
evo_lit_task evo_lit_task_named(const char *env);

/* The network shape a task needs: inputs (2, 6, 3) and outputs (1). */
unsigned evo_lit_n_in(evo_lit_task t);

typedef struct evo_lit_result {
	double fitness;	    /* the paper's fitness (no bonus) */
	long steps;	    /* pole: control steps balanced */
	int solved;	    /* the task's success criterion was met */
	int generalisation; /* DPNV after evo_lit_dpnv_check: 0..625 */
} evo_lit_result;

/* XOR: the four patterns, each from a reset network; fitness
 * (4 - sum |error|)^2, solved when every output is on the right side of
 * 0.5 (>= 0.5 for 1). Returns 0, or -1 with err set when the network does
 * not compile or has not 2 inputs and 1 output. */
int evo_lit_xor(const evo_netdesc *d, evo_lit_result *r, evo_err *err);

/* The pole state: x (m), xdot (m/s), th1 (rad), th1dot (rad/s), th2,
 * th2dot. */
typedef struct evo_lit_pole_state {
	double s[6];
} evo_lit_pole_state;

/* The NEAT paper's start: th1 = 1 degree, everything else 0. */
evo_lit_pole_state evo_lit_pole_start(void);

/* A protocol's start: th1 = 1 degree (NEAT) or 4 degrees (GOMEZ), the
 * rest 0. */
evo_lit_pole_state evo_lit_pole_start_for(evo_lit_protocol pr);

/* Advance by dt seconds with RK4, force (N) held: the NEAT protocol's
 * physics (no cart friction). */
void evo_lit_pole_rk4(evo_lit_pole_state *p, double force, double dt);

/* The same with a protocol's physics (GOMEZ: cart friction 5e-4). */
void evo_lit_pole_rk4_for(evo_lit_protocol pr, evo_lit_pole_state *p,
			  double force, double dt);

/* 1 when a pole is beyond 36 degrees or the cart off the track. */
int evo_lit_pole_failed(const evo_lit_pole_state *p);

/* Balance from *start (NULL: the paper's start) for at most max_steps
 * control steps, the network reset first. velocities picks DPV's inputs
 * or DPNV's. fitness: with velocities the steps balanced; without,
 * Gruau's damping fitness 0.1 t/1000 + 0.9 * 0.75 / sum over the last 100
 * steps of (|x| + |xdot| + |th1| + |th1dot|), the second term 0 when
 * t < 100. solved: max_steps >= EVO_LIT_POLE_SUCCESS were balanced.
 * Returns 0, or -1 with err set (network does not compile or fit). */
int evo_lit_pole(const evo_netdesc *d, int velocities,
		 const evo_lit_pole_state *start, long max_steps,
		 evo_lit_result *r, evo_err *err);

/* The same on a protocol (start NULL: that protocol's start). */
int evo_lit_pole_for(evo_lit_protocol pr, const evo_netdesc *d,
		     int velocities, const evo_lit_pole_state *start,
		     long max_steps, evo_lit_result *r, evo_err *err);

/* Gruau's generalisation test: 625 starts, x, xdot, th1, th1dot each at
 * 0.05, 0.25, 0.5, 0.75, 0.95 of the ranges +-2.16 m, +-1.35 m/s,
 * +-3.6 degrees, +-8.6 degrees/s (th2 = th2dot = 0, as in the NEAT and ESP
 * code); returns how many the network balances for 1,000 steps, or -1
 * with err set. */
int evo_lit_generalisation(const evo_netdesc *d, int velocities, evo_err *err);

/* The same starts on a protocol's physics. */
int evo_lit_generalisation_for(evo_lit_protocol pr, const evo_netdesc *d,
			       int velocities, evo_err *err);

/* The DPNV success test the paper applies to each generation's champion:
 * balance 100,000 steps from the paper's start, then generalise to at
 * least 200 of the 625 starts. Sets r->solved and r->generalisation
 * (-1 when the long run failed and the test was not run). */
int evo_lit_dpnv_check(const evo_netdesc *d, evo_lit_result *r, evo_err *err);

/* The same test on a protocol: 100,000 steps from its start, then the 625
 * starts, all on its physics. */
int evo_lit_dpnv_check_for(evo_lit_protocol pr, const evo_netdesc *d,
			   evo_lit_result *r, evo_err *err);

/* Evaluate one candidate for task t on protocol pr as LEARNSIM does: XOR
 * (pr ignored); DPV up to 100,000 steps; DPNV Gruau's fitness over 1,000
 * steps (solved is left 0: evo_lit_dpnv_check_for decides). */
int evo_lit_evaluate(evo_lit_task t, evo_lit_protocol pr,
		     const evo_netdesc *d, evo_lit_result *r, evo_err *err);

#endif
