/* The 2D scene's episode and its part of the tick (sim/world2d/scene.h):
 * the reset and switching elements off and on; before the physics step
 * every bot's actuators act, after it the poses, movement history and
 * contacts are read back. The tick's order is the scene model's
 * (sim/scene/tick.c, through dim2d.c). This is the top of the 2D world:
 * it calls the pieces below it (actuators.c, grid.c, scene.c), none of
 * which calls back. */
#include <stdint.h>

#include "base/rng.h"
#include "world2d/actuators.h"
#include "world2d/scene.h"
#include "world2d/scene_internal.h"

static void reset_bot(evo_scene *sc, int i)
{
	evo_bot *b = &sc->bot[i];
	evo_bot_release(sc, i);
	evo_scene_place_bot(sc, i, b->def.x, b->def.y, b->def.yaw);
	for (int k = 0; k < b->n_actuators; k++) {
		b->actuator[k].command = b->actuator[k].previous = 0.5;
		b->actuator[k].speed = 0;
	}
	evo_bot_forget_places(b);
	b->touching = b->collisions = b->delivered = b->gathered = 0;
	b->reward = 0;
}

void evo_scene_reset(evo_scene *sc, uint64_t grid_seed, uint64_t episode_seed)
{
	/* A scene of teams, or with objects: claws open, then a fresh
	 * physics world of the same bodies, so that an episode does not
	 * depend on the ones before it, nor on which of a learning run's
	 * workers runs it: Box2D's contacts, the order of its lists and its
	 * broad phase's tree carry over from one episode to the next, and
	 * with several bots that meet, or objects taken off the world and
	 * put back (a delivery disables a body, a reset enables it), they
	 * change the figures; so they may in a maze, where a robot ends
	 * episodes pressed into corners of walls, the order of whose contacts
	 * the tree's history decides. (A scene of one agent without objects
	 * or walls keeps its world, as its golden traces were recorded.) */
	int world_new = sc->n_teams > 0 || sc->n_objects > 0 || sc->n_walls > 0;
	if (world_new) {
		for (int i = 0; i < sc->n_bots; i++)
			evo_bot_release(sc, i);
		/* every object on, so that the new world makes every body
		 * alike, whichever the last episode took off the world */
		for (int k = 0; k < sc->n_objects; k++)
			sc->be->set_enabled(sc->bw,
					    sc->element[sc->object[k]].body, 1);
		sc->be->reset(sc->bw);
	}
	for (int i = 0; i < sc->n_bots; i++)
		reset_bot(sc, i);
	for (int i = 0; i < sc->n_elements; i++) {
		evo_element *e = &sc->element[i];
		e->held_by = -1;
		if (e->kind == EVO_PIECE_OBJECT) {
			e->active = 1;
			/* its starting angle, not the one the last episode
			 * left: a circle's turn changes Box2D's rounding, and
			 * an episode would depend on the one before it */
			e->angle = e->def.angle;
			sc->be->set_enabled(sc->bw, e->body, 1);
			evo_scene_place_element(sc, i, e->def.x, e->def.y);
			/* awake, as a new body, not asleep as the last
			 * episode may have left it */
			sc->be->wake(sc->bw, e->body);
		} else {
			e->active = 1;
			e->x = e->def.x;
			e->y = e->def.y;
		}
	}
	evo_grid_rebuild(sc, grid_seed, world_new);
	evo_core_reset(&sc->core, grid_seed, episode_seed);
}

/* The bot's pose after the physics step. A bot whose collision is
 * "undo" (kinematic) and that now lies closer than its radius to a wall
 * goes back to where it was, turned as it turned: Lehman's maze
 * simulator drops a move that would make the robot hit a wall, and keeps
 * the new heading. Returns 1 when the step was undone. */
static int undo_blocked_step(evo_scene *sc, evo_bot *b)
{
	double x = b->x, y = b->y;
	evo_bot_refresh_pose(sc, b);
	if (!b->def.body.kinematic || !sc->be->blocked(sc->bw, b->body))
		return 0;
	sc->be->set_pose(sc->bw, b->body, (const double[3]){x, y, 0}, b->angle);
	evo_bot_refresh_pose(sc, b);
	return 1;
}

void evo_scene_act(evo_scene_core *c)
{
	evo_scene *sc = (evo_scene *)c;
	for (int i = 0; i < sc->n_bots; i++) {
		for (int k = 0; k < sc->bot[i].n_actuators; k++)
			evo_actuator_act(sc, i, k);
		evo_bot_drive(sc, i);
	}
}

void evo_scene_read_back(evo_scene_core *c)
{
	evo_scene *sc = (evo_scene *)c;
	for (int i = 0; i < sc->n_bots; i++) {
		evo_bot *b = &sc->bot[i];
		int undone = undo_blocked_step(sc, b);
		evo_bot_remember_place(b);
		b->touching = undone || sc->be->touching(sc->bw, b->body);
		/* A held object is welded and does not collide with its
		 * bot, so it never counts. */
		if (b->touching)
			b->collisions++;
	}
	/* Objects follow their bodies. */
	for (int k = 0; k < sc->n_objects; k++) {
		evo_element *e = &sc->element[sc->object[k]];
		if (e->active) {
			evo_bpose p = sc->be->pose(sc->bw, e->body);
			e->x = p.pos[0];
			e->y = p.pos[1];
			e->angle = p.yaw;
		}
	}
}

void evo_scene_set_active(evo_scene *sc, int element, int on)
{
	if (element < 0 || element >= sc->n_elements)
		return;
	evo_element *e = &sc->element[element];
	on = on != 0;
	if (e->kind == EVO_PIECE_OBJECT) {
		if (!on && e->held_by >= 0)
			evo_bot_release(sc, e->held_by);
		sc->be->set_enabled(sc->bw, e->body, on);
	}
	e->active = on;
}
