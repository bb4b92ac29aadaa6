/* evo — the 3D world: a small C API over ODE 0.16 (Debian's libode-dev).
 *
 * sim/world3d/world_ode.c is the only file of evo that includes ODE's
 * headers; everything above it (the 3D scene, its sensors and actuators,
 * the task runner, the viewer) sees only this header, as the 2D world
 * keeps Box2D behind world2d/world.h.
 *
 * Frame and units: metres, kilograms, seconds, radians; right-handed, z
 * up, gravity along -z; a ground plane z = 0 is always there. A body's own
 * frame has x ahead, y to its left and z up (docs/world3d.md).
 *
 * One world per thread at a time: ODE keeps per-thread data, which this
 * file allocates (dAllocateODEDataForThread) the first time a thread
 * creates, steps or ray-casts a world, after ODE itself was set up once
 * (dInitODE2). A world must not be used by two threads at once.
 *
 * Bodies, static shapes and hinges are reached by their index, in the
 * order they were added; a world is made again from its definitions
 * (evo_world3d_destroy, then create and add) rather than patched, so an
 * episode never depends on the one before it. */
#ifndef EVO_WORLD3D_H
#define EVO_WORLD3D_H

#include "scene/backend.h"

typedef struct evo_world3d evo_world3d;

/* The same world behind the backend interface (sim/scene/backend.h): a
 * 3D scene calls it through this struct (sim/world3d/backend_ode.c),
 * which passes its evo_bworld to the functions below, a body id's index
 * being the body's. */
extern const evo_backend evo_backend_ode;

typedef enum evo_shape3d_type {
	EVO_SHAPE3D_BOX = 0,
	EVO_SHAPE3D_SPHERE = 1,
	EVO_SHAPE3D_CYLINDER = 2,
} evo_shape3d_type;

/* Categories of shapes: a ray sees those in its mask. */
#define EVO_CAT3D_GROUND   0x1u
#define EVO_CAT3D_BOT	   0x2u
#define EVO_CAT3D_OBSTACLE 0x4u
#define EVO_CAT3D_OBJECT   0x8u
#define EVO_CAT3D_ALL	   0xFu

typedef struct evo_shape3d {
	evo_shape3d_type type;
	/* A static shape: its centre in the world, turned by yaw about z.
	 * A body's shape: its centre in the body's frame, not turned. */
	double pos[3];
	double yaw;
	double half[3];	    /* box: half sides along x, y, z */
	double radius;	    /* sphere, cylinder */
	double half_length; /* cylinder */
	int axis;	    /* cylinder: its axis, 0 x, 1 y, 2 z */
	double friction;    /* Coulomb's mu; 0: slides freely */
	unsigned category;  /* EVO_CAT3D_* */
} evo_shape3d;

#define EVO_BODY3D_MAX_SHAPES 4

typedef struct evo_body3d_def {
	double pos[3];
	double yaw;  /* about z, radians */
	double mass; /* kilograms; the first shape gives the inertia */
	int n_shapes;
	evo_shape3d shape[EVO_BODY3D_MAX_SHAPES];
	/* Shapes of one group (>= 0) never collide with each other (a
	 * robot's chassis and its wheels), and touching is counted per
	 * group; -1: a group of its own. */
	int group;
} evo_body3d_def;

typedef struct evo_world3d_def {
	double step;		/* seconds per physics step (1/60) */
	double gravity;		/* m/s^2 along -z (9.81) */
	double erp, cfm;	/* ODE's error reduction and constraint force
				   mixing (0.2, 1e-6) */
	double ground_friction; /* 1 */
	/* A body faster than this (m/s) or spinning faster than max_spin
	 * (rad/s), or with a position or speed that is not a number, has
	 * exploded: evo_world3d_step reports it. */
	double max_speed, max_spin; /* 100, 1000 */
} evo_world3d_def;

evo_world3d_def evo_default_world3d_def(void);

/* NULL when the definition is invalid or memory runs out. */
evo_world3d *evo_world3d_create(const evo_world3d_def *def);
void evo_world3d_destroy(evo_world3d *w);

/* A static shape (world frame); its index, or -1 for a size that is not
 * positive. */
int evo_world3d_add_static(evo_world3d *w, const evo_shape3d *s);

/* A dynamic body; its index, or -1 (no shape, a size or mass that is not
 * positive). */
int evo_world3d_add_body(evo_world3d *w, const evo_body3d_def *def);

/* A hinge between bodies a and b at a world point, turning about a world
 * axis; its index, or -1. */
int evo_world3d_add_hinge(evo_world3d *w, int a, int b, const double anchor[3],
			  const double axis[3]);

/* A hinge's motor for the next step: a torque (N m) about its axis, or a
 * target rate (rad/s) reached with at most fmax (N m). */
void evo_world3d_hinge_torque(evo_world3d *w, int hinge, double torque);
void evo_world3d_hinge_velocity(evo_world3d *w, int hinge, double rate,
				double fmax);
/* Its rate now (rad/s). */
double evo_world3d_hinge_rate(const evo_world3d *w, int hinge);

/* A body's pose: its centre, and R (row-major) that turns a vector of the
 * body's frame into the world's: world = R body. */
void evo_body3d_pose(const evo_world3d *w, int body, double pos[3],
		     double R[9]);
void evo_body3d_velocity(const evo_world3d *w, int body, double v[3],
			 double omega[3]);
void evo_body3d_set_velocity(evo_world3d *w, int body, const double v[3],
			     const double omega[3]);
void evo_body3d_set_position(evo_world3d *w, int body, const double pos[3]);
/* Take a body out of the world (enabled 0: it stops where it is, and no
 * contact, ray or step sees it) or put it back (1). */
void evo_body3d_set_enabled(evo_world3d *w, int body, int enabled);
double evo_body3d_mass(const evo_world3d *w, int body);

/* Forces for the next step only (ODE clears them when it steps): a force
 * of the world's frame at a point of the body's frame, a force of the
 * body's frame at a point of its frame, a torque of the world's frame. */
void evo_body3d_add_force_at(evo_world3d *w, int body, const double f[3],
			     const double at[3]);
void evo_body3d_add_rel_force_at(evo_world3d *w, int body, const double f[3],
				 const double at[3]);
void evo_body3d_add_torque(evo_world3d *w, int body, const double t[3]);
/* The same with the point in the world's frame: a force of the world's
 * frame, or of the body's. */
void evo_body3d_add_force_at_pos(evo_world3d *w, int body, const double f[3],
				 const double at[3]);
void evo_body3d_add_rel_force_at_pos(evo_world3d *w, int body,
				     const double f[3], const double at[3]);

/* Put a body at pos, turned by yaw about z (upright). */
void evo_body3d_set_pose(evo_world3d *w, int body, const double pos[3],
			 double yaw);

/* The group of a body's shapes (evo_body3d_def), -1 for one of its own. */
int evo_body3d_group(const evo_world3d *w, int body);

/* One physics step. Returns 0, or -1 when a body exploded (see
 * evo_world3d_def), with *fault saying which and how (the backend's
 * evo_bfault, sim/scene/backend.h). The world is then no longer worth
 * stepping: make it again. */
int evo_world3d_step(evo_world3d *w, evo_bfault *fault);

/* Contacts in the last step between a shape of group g and a shape of
 * another group that is not the ground. */
int evo_world3d_group_touching(const evo_world3d *w, int group);

/* Which shapes a group touched (not the ground, and not a shape of the
 * same group) in the steps since the last evo_world3d_forget_touches: 1
 * when group touched the static `geom` (evo_world3d_add_static's index),
 * or a shape of body `body`. A world keeps these pairs only once
 * evo_world3d_forget_touches has been called: a world nobody asks does
 * not pay for them. */
void evo_world3d_forget_touches(evo_world3d *w);
int evo_world3d_group_touched(const evo_world3d *w, int group, int geom);
int evo_world3d_group_touched_body(const evo_world3d *w, int group, int body);

/* The nearest hit of the ray from `from` along the unit vector dir, up to
 * len, among shapes whose category is in mask and whose group is not
 * ignore_group: its distance, or -1 when nothing is within len. */
double evo_world3d_raycast(evo_world3d *w, const double from[3],
			   const double dir[3], double len, unsigned mask,
			   int ignore_group);

int evo_world3d_n_bodies(const evo_world3d *w);

#endif
