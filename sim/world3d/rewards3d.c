/* evo — the 3D scene as the scene model's rewards and controls read it
 * (sim/scene/scoring.h, which computes them, the same as in 2D): its bots'
 * contacts, motion, sensors and motors, and the distance to an element
 * (none to one set off).
 * The kinds only 2D has (Collect, Gather: objects carried) say so in
 * their rows of sim/scene/kinds.c and are refused when added. */
#include <math.h>

#include "world3d/scene3d.h"
#include "world3d/scene3d_internal.h"

static int touching(const void *sc, int bot)
{
	return ((const evo_scene3d *)sc)->bot[bot].touching;
}

/* The hull's velocity and its x axis (its heading) in the world. */
static void motion(const void *sc, int bot, double v[3], double ahead[3])
{
	const evo_bot *b = &((const evo_scene3d *)sc)->bot[bot];
	for (int k = 0; k < 3; k++) {
		v[k] = b->v[k];
		ahead[k] = b->R[3 * k];
	}
}

static double distance(const void *v, int bot, int target)
{
	const evo_scene3d *sc = v;
	if (target < 0 || target >= sc->n_elements ||
	    !sc->element[target].active)
		return -1;
	return evo_scene3d_distance(sc, bot, target);
}

/* Every actuator of a 3D bot moves it: its wheels and propellers. */
static double effort(const void *v, int bot)
{
	const evo_bot *b = &((const evo_scene3d *)v)->bot[bot];
	double sum = 0;
	for (int i = 0; i < b->n_actuators; i++)
		sum += evo_effort_term(b->actuator[i].command);
	return sum;
}

const evo_score_ops evo_score_ops_3d = {
    .touching = touching,
    .motion = motion,
    .distance = distance,
    .effort = effort,
};
