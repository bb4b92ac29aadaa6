/* evo — private to sim/world3d/: what the 3D scene's files share. No other
 * folder includes it. */
#ifndef EVO_SCENE3D_INTERNAL_H
#define EVO_SCENE3D_INTERNAL_H

#include "world3d/scene3d.h"

/* scene3d.c: make the world again from the definitions, the bots at their
 * starts, the episode's obstacles in place. 0, or -1 with sc->err set. */
int evo_scene3d_build_world(evo_scene3d *sc);

/* A body of the 3D world as the backend names it. */
static inline evo_body_id evo_scene3d_body(int body)
{
	return (evo_body_id){body, 0};
}

/* A body's centre and turn (R, world = R body). */
static inline void evo_scene3d_pose(const evo_scene3d *sc, int body,
				    double pos[3], double R[9])
{
	evo_bpose p = sc->be->pose(sc->bw, evo_scene3d_body(body));
	for (int k = 0; k < 3; k++)
		pos[k] = p.pos[k];
	for (int k = 0; k < 9; k++)
		R[k] = p.R[k];
}

/* Each bot's pose and speeds from its hull's body. */
void evo_scene3d_refresh_bots(evo_scene3d *sc);

/* actuators3d.c: before each physics step, the bot's actuators and the
 * forces of the water or air around it (buoyancy, drag). */
void evo_bot3d_act(evo_scene3d *sc, int bot);

/* How the scene model reads a 3D scene (rewards3d.c), and what it asks
 * of one (dim3d.c). */
extern const evo_score_ops evo_score_ops_3d;
extern const evo_scene_dim evo_scene_dim_3d;

/* step3d.c: after the tick's physics, the bots' poses, speeds and
 * contacts and the objects' poses read back; a body that exploded said
 * in sc->fault, its penalty returned. */
void evo_scene3d_read_back(evo_scene_core *c);
double evo_scene3d_fault(evo_scene_core *c, const evo_bfault *f);

/* The distance from bot b's centre to element e's. */
double evo_scene3d_distance(const evo_scene3d *sc, int bot, int element);

#endif
