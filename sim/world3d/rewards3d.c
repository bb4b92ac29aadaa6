/* The 3D reward and control functions (sim/world3d/scene3d.h): the 2D
 * ones that make sense in 3D, with the same names in Lua. */
#include <math.h>

#include "world3d/scene3d.h"
#include "world3d/scene3d_internal.h"

void evo_reward3d_reset(evo_scene3d *sc, evo_reward3d *r)
{
	(void)sc;
	r->previous = -1;
	r->total = 0;
}

/* The bot's speed along its heading (its x axis). */
static double forward_speed(const evo_bot3d *b)
{
	return b->v[0] * b->R[0] + b->v[1] * b->R[3] + b->v[2] * b->R[6];
}

double evo_reward3d_compute(evo_scene3d *sc, evo_reward3d *r)
{
	const evo_reward3d_def *d = &r->def;
	const evo_bot3d *b = &sc->bot[d->bot];
	double v = 0;
	switch (d->kind) {
	case EVO_RW_CLOSING_ON_TARGET: {
		double dist = evo_scene3d_distance(sc, d->bot, d->target);
		if (r->previous >= 0)
			v = d->k * (r->previous - dist);
		r->previous = dist;
		break;
	}
	case EVO_RW_SENSOR_OVER:
		for (int i = 0; i < d->n_sensors; i++) {
			double s = b->sensor[d->sensor[i]].value;
			if (s > d->threshold)
				v += d->k * (s - d->threshold);
		}
		break;
	case EVO_RW_SENSOR_UNDER:
		for (int i = 0; i < d->n_sensors; i++) {
			double s = b->sensor[d->sensor[i]].value;
			if (s <= d->threshold)
				v += d->k * (d->threshold - s);
		}
		break;
	case EVO_RW_PUNISH_ON_COLLISION:
		v = b->touching ? d->k : 0;
		break;
	case EVO_RW_FORWARD_MOTION: {
		double f = forward_speed(b);
		v = f > 0.01 ? d->k : f < -0.01 ? d->k2 : 0;
		break;
	}
	case EVO_RW_FORWARD_SPEED:
		v = d->k * forward_speed(b);
		break;
	case EVO_RW_SPEED:
		v = d->k *
		    (b->v[0] * b->v[0] + b->v[1] * b->v[1] + b->v[2] * b->v[2]);
		break;
	case EVO_RW_STEP:
		v = d->k;
		break;
	default: /* 2D only: refused when added */
		break;
	}
	if (!isfinite(v))
		v = 0;
	r->total += v;
	return v;
}

int evo_control3d_check(evo_scene3d *sc, const evo_control3d *c)
{
	const evo_bot3d *b = &sc->bot[c->def.bot];
	switch (c->def.kind) {
	case EVO_CF_NEXT_ON_TIMEOUT:
		return sc->tick >= c->def.ticks;
	case EVO_CF_NEXT_ON_COLLISION:
		return b->touching > 0;
	case EVO_CF_NEXT_ON_COLLISION_AND_TIMEOUT:
		return b->touching > 0 || sc->tick >= c->def.ticks;
	case EVO_CF_NEXT_ON_SENSOR_BELOW:
		return b->sensor[c->def.sensor].value < c->def.threshold;
	default: /* 2D only: refused when added */
		break;
	}
	return 0;
}
