/* The 3D scene's episode and tick (sim/world3d/scene3d.h): the reset, the
 * sensing, and the step (actuators act and the physics steps, substeps
 * times; then the rewards, the post-step hook and the controls of the
 * scene model, sim/scene/scoring.c). The top of the 3D world: it calls the
 * pieces below it, none of which calls back. */
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
		evo_bot3d *b = &sc->bot[i];
		memcpy(b->start, b->def.pos, sizeof b->start);
		b->start_yaw = b->def.yaw;
		for (int k = 0; k < b->n_actuators; k++)
			b->actuator[k].command = 0.5;
		b->touching = b->collisions = 0;
		b->reward = 0;
	}
	for (int i = 0; i < sc->n_elements; i++)
		memcpy(sc->element[i].pos, sc->element[i].def.pos,
		       sizeof sc->element[i].pos);
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

/* Which bot (or object) a body of the world is, for the fault message. */
static void describe_fault(evo_scene3d *sc, const evo_bfault *f)
{
	int body = f->body.index;
	const char *what = "a body";
	for (int i = 0; i < sc->n_bots; i++) {
		if (sc->bot[i].body == body)
			what = sc->bot[i].name;
		for (int k = 0; k < sc->bot[i].n_actuators; k++)
			if (sc->bot[i].actuator[k].body == body)
				what = sc->bot[i].actuator[k].name;
	}
	for (int i = 0; i < sc->n_elements; i++)
		if (sc->element[i].body == body)
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
}

int evo_scene3d_step(evo_scene3d *sc)
{
	if (sc->fault[0])
		return 1;
	for (int i = 0; i < sc->n_bots; i++)
		sc->bot[i].touching = 0;
	for (int s = 0; s < sc->def.substeps; s++) {
		for (int i = 0; i < sc->n_bots; i++)
			evo_bot3d_act(sc, i);
		evo_bfault f;
		if (sc->be->step(sc->bw, &f)) {
			sc->tick++;
			describe_fault(sc, &f);
			sc->step_reward = sc->def.fault_penalty;
			sc->episode_reward += sc->def.fault_penalty;
			return 1;
		}
		for (int i = 0; i < sc->n_bots; i++)
			sc->bot[i].touching += sc->be->touching(
			    sc->bw, evo_scene3d_body(sc->bot[i].body));
	}
	sc->tick++;
	evo_scene3d_refresh_bots(sc);
	for (int i = 0; i < sc->n_bots; i++)
		if (sc->bot[i].touching)
			sc->bot[i].collisions++;
	for (int i = 0; i < sc->n_elements; i++) {
		evo_element3d *e = &sc->element[i];
		if (e->body >= 0)
			evo_scene3d_pose(sc, e->body, e->pos, e->R);
	}
	/* rewards, the post-step hook, controls: the scene model's */
	return evo_core_score(&sc->core);
}
