/* The 3D actuators (sim/world3d/scene3d.h): wheels on hinges, driven by a
 * target rate or a torque, and propellers that push along an axis; and
 * the forces of the water or air a bot moves in (buoyancy, drag). A
 * command of 0.5 is neutral everywhere: (2c - 1) times the maximum, c
 * clamped into [0, 1] as in 2D (evo_command01). */
#include <math.h>

#include "world3d/scene3d.h"
#include "world3d/scene3d_internal.h"

static void act(evo_scene3d *sc, int bot, const evo_actuator *a)
{
	const evo_bot *b = &sc->bot[bot];
	double u = 2 * evo_command01(a->command) - 1;
	if (a->def.kind == EVO_ACT_BROADCAST)
		return; /* heard through its command */
	if (a->def.kind == EVO_ACT_WHEEL) {
		if (a->hinge < 0)
			return;
		if (a->def.torque_mode)
			sc->be->hinge_torque(sc->bw, a->hinge,
					     u * a->def.max_torque);
		else
			sc->be->hinge_velocity(sc->bw, a->hinge,
					       u * a->def.max_rate,
					       a->def.max_torque);
	} else if (a->def.kind == EVO_ACT_PROPELLER) {
		double f[3];
		for (int k = 0; k < 3; k++)
			f[k] = u * a->def.max_thrust * a->def.axis[k];
		sc->be->apply_force_at(sc->bw, b->body, f,
				       a->def.pos,
				       EVO_BFORCE_BODY | EVO_BPOINT_BODY);
	}
}

void evo_bot3d_act(evo_scene3d *sc, int bot)
{
	evo_bot *b = &sc->bot[bot];
	const evo_bot_def *d = &b->def;
	for (int k = 0; k < b->n_actuators; k++)
		act(sc, bot, &b->actuator[k]);
	if (d->buoyancy > 0) {
		double up[3] = {0, 0,
				d->buoyancy * d->mass * sc->def.world.gravity};
		sc->be->apply_force_at(sc->bw, b->body, up,
				       d->cob, EVO_BPOINT_BODY);
	}
	if (d->drag_linear > 0 || d->drag_quadratic > 0 ||
	    d->drag_angular > 0) {
		double v[3], w[3], f[3], t[3];
		static const double centre[3] = {0, 0, 0};
		sc->be->velocity(sc->bw, b->body, v, w);
		double speed = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
		double k = d->drag_linear + d->drag_quadratic * speed;
		for (int i = 0; i < 3; i++) {
			f[i] = -k * v[i];
			t[i] = -d->drag_angular * w[i];
		}
		sc->be->apply_force_at(sc->bw, b->body, f,
				       centre, EVO_BPOINT_BODY);
		sc->be->add_torque(sc->bw, b->body, t);
	}
}
