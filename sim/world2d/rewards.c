/* evo — the 2D scene as the scene model's rewards and controls read it
 * (sim/scene/scoring.h, which computes them): its bots' contacts, motion,
 * sensors, wheels and targets, and the kinds only 2D has by their rows in
 * sim/scene/kinds.c: Collect and Gather (objects carried or gathered).
 * The scene model pays them through evo_score_ops_2d
 * (scene/core.c's evo_core_score). */
#include "world2d/rewards.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "world2d/actuators.h"
#include "world2d/query.h"
#include "world2d/scene_internal.h"

/* ---- helpers ------------------------------------------------------------ */

static evo_element *element_at(evo_scene *sc, int e)
{
	return e >= 0 && e < sc->n_elements ? &sc->element[e] : NULL;
}

/* ---- what the scoring reads --------------------------------------------- */

static int touching(const void *sc, int bot)
{
	return ((const evo_scene *)sc)->bot[bot].touching;
}

/* The body's velocity, and the heading the pose left (cos, sin). */
static void motion(const void *v, int bot, double vel[3], double ahead[3])
{
	const evo_scene *sc = v;
	const evo_bot *b = &sc->bot[bot];
	double w[3];
	sc->be->velocity(sc->bw, b->body, vel, w);
	ahead[0] = b->c;
	ahead[1] = b->s;
	ahead[2] = 0;
}

static double distance(const void *v, int bot, int target)
{
	const evo_scene *sc = v;
	const evo_bot *b = &sc->bot[bot];
	double tx, ty;
	if (!evo_scene_target_pos(sc, bot, target, &tx, &ty))
		return -1;
	return hypot(tx - b->x, ty - b->y);
}

/* The bot's wheels of either kind. */
static double effort(const void *v, int bot)
{
	const evo_bot *b = &((const evo_scene *)v)->bot[bot];
	double sum = 0;
	for (int i = 0; i < b->n_actuators; i++) {
		const evo_actuator *a = &b->actuator[i];
		if (a->def.kind != EVO_ACT_WHEEL &&
		    a->def.kind != EVO_ACT_SPEED_WHEEL)
			continue;
		sum += evo_effort_term(a->command);
	}
	return sum;
}

/* ---- the kinds only 2D has ---------------------------------------------- */

/* Collect: k for each active object the bot holds whose centre lies in the
 * target zone (an active EVO_PIECE_ZONE; anything else gives 0). A delivery
 * opens the bot's claws (all of them), takes the object off the world
 * until the next reset and counts it in bot->delivered.
 *
 * EvoAgents crashed here by destroying a body still welded to the claw.
 * The order below avoids that and handles several objects in one step:
 * first mark every delivered object inactive (the claws still say who
 * holds what), then open the claws (removing the welds), and only then
 * disable the bodies of inactive objects. Disabling is idempotent, and an
 * inactive object is off the world by definition, so the second pass
 * needs no list of its own. */
static double collect(evo_scene *sc, const evo_reward *r, evo_bot *b)
{
	const evo_element *z = element_at(sc, r->def.target);
	int n = 0;
	if (!z || z->kind != EVO_PIECE_ZONE || !z->active)
		return 0;
	for (int i = 0; i < sc->n_elements; i++) {
		evo_element *e = &sc->element[i];
		if (e->kind != EVO_PIECE_OBJECT || !e->active ||
		    e->held_by != r->def.bot)
			continue;
		evo_bpose p = sc->be->pose(sc->bw, e->body);
		if (!evo_zone_contains(z, p.pos[0], p.pos[1]))
			continue;
		e->active = 0;
		n++;
	}
	if (n == 0)
		return 0;
	evo_bot_release(sc, r->def.bot);
	for (int i = 0; i < sc->n_elements; i++) {
		evo_element *e = &sc->element[i];
		if (e->kind == EVO_PIECE_OBJECT && !e->active)
			sc->be->set_enabled(sc->bw, e->body, 0);
	}
	b->delivered += n;
	return r->def.k * n;
}

/* Gather (evo's own, for foraging, docs/teams.md): k for each active
 * object no claw holds that the bot touches, its centre within the bot's
 * radius + its own + EVO_GATHER_GAP; the object leaves the world until
 * the next reset (or until the environment places and activates it
 * again) and counts in bot->gathered. The objects are found through the
 * broad phase, near the bot. */
#define EVO_GATHER_GAP 0.1
#define GATHER_CAP     32

static double gather(evo_scene *sc, const evo_reward *r, evo_bot *b)
{
	evo_shape_info local[GATHER_CAP], *found = local;
	/* an object of radius up to 2 m is found; a larger one needs a
	 * larger square */
	double reach = b->radius + 2 + EVO_GATHER_GAP;
	double x0 = b->x - reach, y0 = b->y - reach;
	double x1 = b->x + reach, y1 = b->y + reach;
	int n = evo_scene_query(sc, x0, y0, x1, y1, EVO_CAT_OBJECT, local,
				GATHER_CAP);
	if (n > GATHER_CAP) {
		/* a heap of objects: room for all of them */
		evo_shape_info *big = malloc((size_t)n * sizeof *big);
		if (big) {
			found = big;
			n = evo_scene_query(sc, x0, y0, x1, y1, EVO_CAT_OBJECT,
					    big, n);
		} else {
			n = GATHER_CAP;
		}
	}
	int got = 0;
	for (int i = 0; i < n; i++) {
		int k = evo_scene_object_of_body(sc, found[i].body.index);
		evo_element *e = element_at(sc, k);
		if (!e || !e->active || e->held_by >= 0)
			continue;
		double lim = b->radius + e->size + EVO_GATHER_GAP;
		double dx = found[i].x - b->x, dy = found[i].y - b->y;
		if (dx * dx + dy * dy > lim * lim)
			continue;
		e->active = 0;
		sc->be->set_enabled(sc->bw, e->body, 0);
		got++;
	}
	if (found != local)
		free(found);
	b->gathered += got;
	return r->def.k * got;
}

/* Collect and Gather, the rewards of 2D alone. */
static double own_reward(void *v, const evo_reward *r)
{
	evo_scene *sc = v;
	evo_bot *b = &sc->bot[r->def.bot];
	if (r->def.kind == EVO_RW_COLLECT)
		return collect(sc, r, b);
	if (r->def.kind == EVO_RW_GATHER)
		return gather(sc, r, b);
	return 0;
}

const evo_score_ops evo_score_ops_2d = {
    .touching = touching,
    .motion = motion,
    .distance = distance,
    .effort = effort,
    .own_reward = own_reward,
};

static evo_scored scored(evo_scene *sc)
{
	return (evo_scored){&evo_score_ops_2d, sc, &sc->hooks, &sc->err};
}

double evo_reward_compute(evo_scene *sc, evo_reward *r, int *failed)
{
	evo_scored s = scored(sc);
	return evo_reward_compute_in(&s, r, failed);
}

int evo_control_check(evo_scene *sc, evo_control *c)
{
	evo_scored s = scored(sc);
	return evo_control_check_in(&s, c);
}
