/* The 3D scene's episode and its part of the tick (sim/world3d/scene3d.h):
 * the reset, placing bots and elements, switching elements off and on,
 * the poses and contacts read back after the physics, and the message of
 * a body that exploded. The tick's order is the scene model's
 * (sim/scene/tick.c, through dim3d.c). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "world3d/scene3d.h"
#include "world3d/scene3d_internal.h"

int evo_scene3d_reset(evo_scene3d *sc, uint64_t grid_seed,
		      uint64_t episode_seed)
{
	sc->n_obstacles = sc->n_fixed_obstacles;
	for (int i = 0; i < sc->n_bots; i++) {
		evo_bot *b = &sc->bot[i];
		memcpy(b->start, b->def.pos, sizeof b->start);
		b->start_yaw = b->def.yaw;
		for (int k = 0; k < b->n_actuators; k++)
			b->actuator[k].command = 0.5;
		b->touching = b->collisions = 0;
		b->reward = 0;
		evo_bot_forget_places(b);
	}
	for (int i = 0; i < sc->n_elements; i++) {
		memcpy(sc->element[i].pos, sc->element[i].def.pos,
		       sizeof sc->element[i].pos);
		sc->element[i].active = 1;
	}
	evo_core_reset(&sc->core, grid_seed, episode_seed);
	return evo_scene3d_build_world(sc);
}

int evo_scene3d_place_bot(evo_scene3d *sc, int bot, const double pos[3],
			  double yaw)
{
	if (bot < 0 || bot >= sc->n_bots)
		return evo_fail(&sc->err, "no bot %d", bot);
	if (!isfinite(pos[0]) || !isfinite(pos[1]) || !isfinite(pos[2]) ||
	    !isfinite(yaw))
		return evo_fail(&sc->err, "a pose that is not a number");
	memcpy(sc->bot[bot].start, pos, sizeof sc->bot[bot].start);
	sc->bot[bot].start_yaw = yaw;
	return evo_scene3d_build_world(sc);
}

void evo_scene3d_place_element(evo_scene3d *sc, int element,
			       const double pos[3])
{
	memcpy(sc->element[element].pos, pos, sizeof sc->element[element].pos);
}

void evo_scene3d_set_active(evo_scene3d *sc, int element, int on)
{
	if (element < 0 || element >= sc->n_elements)
		return;
	evo_element *e = &sc->element[element];
	on = on != 0;
	if (e->kind == EVO_PIECE_OBJECT && e->body.index >= 0 &&
	    e->active != on)
		sc->be->set_enabled(sc->bw, e->body, on);
	e->active = on;
}

/* Which bot (or object) a body of the world is, in the fault message. */
double evo_scene3d_fault(evo_scene_core *c, const evo_bfault *f)
{
	evo_scene3d *sc = (evo_scene3d *)c;
	int body = f->body.index;
	const char *what = "a body";
	for (int i = 0; i < sc->n_bots; i++) {
		if (sc->bot[i].body.index == body)
			what = sc->bot[i].name;
		for (int k = 0; k < sc->bot[i].n_actuators; k++)
			if (sc->bot[i].actuator[k].body == body)
				what = sc->bot[i].actuator[k].name;
	}
	for (int i = 0; i < sc->n_elements; i++)
		if (sc->element[i].body.index == body)
			what = sc->element[i].name;
	char how[96];
	if (f->kind == EVO_BFAULT_NAN)
		snprintf(how, sizeof how,
			 "its position or speed is not a number");
	else if (f->kind == EVO_BFAULT_SPEED)
		snprintf(how, sizeof how, "it moved at %.3g m/s (max_speed %g)",
			 f->value, sc->def.world.max_speed);
	else
		snprintf(how, sizeof how, "it spun at %.3g rad/s (max_spin %g)",
			 f->value, sc->def.world.max_spin);
	snprintf(sc->fault, sizeof sc->fault,
		 "%s exploded at tick %ld: %s; the episode ends with a penalty "
		 "of %g",
		 what, sc->tick, how, sc->def.fault_penalty);
	return sc->def.fault_penalty;
}

void evo_scene3d_read_back(evo_scene_core *c)
{
	evo_scene3d *sc = (evo_scene3d *)c;
	evo_scene3d_refresh_bots(sc);
	for (int i = 0; i < sc->n_bots; i++) {
		evo_bot_remember_place(&sc->bot[i]);
		if (sc->bot[i].touching)
			sc->bot[i].collisions++;
	}
	for (int i = 0; i < sc->n_elements; i++) {
		evo_element *e = &sc->element[i];
		if (e->body.index >= 0)
			evo_scene3d_pose(sc, e->body.index, e->pos, e->R);
	}
}
