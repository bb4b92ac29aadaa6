/* evo — the 2D world: a small C API over Box2D 2.4.
 *
 * sim/world2d/world_box2d.cpp is the only C++ file in evo; everything above it
 * (sensors, actuators, environments, the task runner) is C and sees only
 * this header. Units are Box2D's (metres, kilograms, seconds, radians);
 * the world has no gravity (it is seen from above) and steps 30 times a
 * simulated second with 8 velocity and 3 position iterations, as
 * EvoAgents did.
 *
 * Bodies are reached through ids (index + generation), the Box2D v3 way:
 * an id of a removed body is refused instead of touching freed memory. */
#ifndef EVO_WORLD_H
#define EVO_WORLD_H

#include <stdint.h>

#include "scene/backend.h"

#ifdef __cplusplus
extern "C" {
#endif

/* No C++ exception leaves these functions (sim/world2d/world_box2d.cpp
 * catches std::bad_alloc where it can arise and returns the failure
 * value): unwinding through C callers is undefined. Under C++ the
 * promise is checked: anything else that escaped would terminate. */
#ifdef __cplusplus
#define EVO_WORLD_NOEXCEPT noexcept
#else
#define EVO_WORLD_NOEXCEPT
#endif

typedef struct evo_world evo_world;

/* The same world behind the backend interface (sim/scene/backend.h): a
 * 2D scene calls it through this struct (sim/world2d/backend_box2d.c),
 * which passes its evo_bworld to the functions below. evo_body_id,
 * evo_shape_type and evo_shape_info are the interface's. */
extern const evo_backend evo_backend_box2d;

/* Collision categories: a body collides with another when each one's
 * category is in the other's mask. */
#define EVO_CAT_BOT 0x0001u
#define EVO_CAT_OBSTACLE 0x0002u
#define EVO_CAT_OBJECT 0x0004u
/* A bot of team k (0 .. 11) has EVO_CAT_BOT and EVO_CAT_TEAM(k), so a ray
 * can see every bot, its teammates or its opponents (docs/teams.md). */
#define EVO_CAT_TEAM(k) ((uint16_t)(0x0008u << (k)))
#define EVO_CAT_TEAMS	0x7FF8u
#define EVO_CAT_ALL 0xFFFFu

typedef struct evo_body_def {
	int dynamic; /* 0: static, never moves */
	/* with dynamic: a kinematic body, moved by its velocity alone and
	 * never pushed back by what it meets (the mazes' robots, whose
	 * colliding steps evo_world_body_blocked finds and the scene undoes) */
	int kinematic;
	double x, y, angle;
	evo_shape_type shape;
	double radius;	       /* circle */
	double half_w, half_h; /* box */
	double density, friction, restitution;
	double linear_damping, angular_damping;
	int allow_sleep;
	uint16_t category, mask;
} evo_body_def;

/* A static circle of radius 1 at the origin, density 1, no friction. */
evo_body_def evo_default_body_def(void) EVO_WORLD_NOEXCEPT;

typedef struct evo_world_def {
	double step;	/* seconds per step, 1/30 */
	int velocity_iterations; /* 8 */
	int position_iterations; /* 3 */
} evo_world_def;

evo_world_def evo_default_world_def(void) EVO_WORLD_NOEXCEPT;

evo_world *evo_world_create(const evo_world_def *def) EVO_WORLD_NOEXCEPT;
void evo_world_destroy(evo_world *w) EVO_WORLD_NOEXCEPT;

/* Make the world again: every body of it, with the same id, where and as
 * it was added (enabled or not), and no obstacles, joints or contacts, so
 * that what follows does not depend on what went before (evo_scene_reset
 * does it before each episode). */
void evo_world_reset(evo_world *w) EVO_WORLD_NOEXCEPT;

/* One physics step. */
void evo_world_step(evo_world *w) EVO_WORLD_NOEXCEPT;

/* Add a body; EVO_BODY_NONE when the definition is invalid (a size that
 * is not positive) or memory runs out. */
evo_body_id evo_world_add_body(evo_world *w,
			       const evo_body_def *def) EVO_WORLD_NOEXCEPT;

/* Remove a body; returns 0, or -1 for a stale or invalid id. */
int evo_world_remove_body(evo_world *w, evo_body_id id) EVO_WORLD_NOEXCEPT;

/* 1 when id names a body of w. */
int evo_body_valid(const evo_world *w, evo_body_id id) EVO_WORLD_NOEXCEPT;

/* Static obstacles, as fixtures of one static body: the way to add the
 * hundreds of a grid cheaply. Returns the obstacle's index. */
int evo_world_add_static_circle(evo_world *w, double x, double y,
				double r) EVO_WORLD_NOEXCEPT;
int evo_world_add_static_box(evo_world *w, double x, double y, double half_w,
			     double half_h, double angle) EVO_WORLD_NOEXCEPT;

typedef struct evo_pose {
	double x, y, angle;
} evo_pose;

/* A wall of no thickness from (x1, y1) to (x2, y2): the segments of the
 * mazes (docs/world.md), with friction 1 (a bot of no friction slides
 * along it). Returns the obstacle's index, or -1 when the two ends are
 * closer than Box2D can tell apart (about 5 mm). */
int evo_world_add_static_segment(evo_world *w, double x1, double y1,
				 double x2, double y2) EVO_WORLD_NOEXCEPT;

evo_pose evo_body_pose(const evo_world *w, evo_body_id id) EVO_WORLD_NOEXCEPT;
void evo_body_set_pose(evo_world *w, evo_body_id id,
		       evo_pose p) EVO_WORLD_NOEXCEPT;
void evo_body_velocity(const evo_world *w, evo_body_id id, double *vx,
		       double *vy, double *omega) EVO_WORLD_NOEXCEPT;
void evo_body_set_velocity(evo_world *w, evo_body_id id, double vx, double vy,
			   double omega) EVO_WORLD_NOEXCEPT;

/* Apply a force (newtons, world frame) at a world point. */
void evo_body_apply_force(evo_world *w, evo_body_id id, double fx, double fy,
			  double px, double py) EVO_WORLD_NOEXCEPT;

/* Apply a torque (newton metres) about the body's centre. */
void evo_body_apply_torque(evo_world *w, evo_body_id id,
			   double torque) EVO_WORLD_NOEXCEPT;

/* 1 when body id, where it is now, lies closer than its radius to a
 * static obstacle or another body whose category its mask takes: for a
 * circle, its centre closer than its radius to the other shape (Box2D's
 * distance between the centre and the shape, without its skin), as
 * Lehman's maze simulator tests a move; for a box, the two shapes
 * overlap. 0 for an invalid id. */
int evo_world_body_blocked(const evo_world *w,
			   evo_body_id id) EVO_WORLD_NOEXCEPT;

/* Number of bodies or obstacles a body is touching now. */
int evo_body_touching(const evo_world *w, evo_body_id id) EVO_WORLD_NOEXCEPT;

/* 1 when body id touches body other, or obstacle `obstacle`, now. */
int evo_body_touching_body(const evo_world *w, evo_body_id id,
			   evo_body_id other) EVO_WORLD_NOEXCEPT;
int evo_body_touching_obstacle(const evo_world *w, evo_body_id id,
			       int obstacle) EVO_WORLD_NOEXCEPT;

/* Remove every static obstacle; indices start again at 0. */
void evo_world_clear_obstacles(evo_world *w) EVO_WORLD_NOEXCEPT;

/* A disabled body takes no part in collisions, queries or ray casts. */
void evo_body_set_enabled(evo_world *w, evo_body_id id,
			  int enabled) EVO_WORLD_NOEXCEPT;

/* Wake a body and restart its time at rest, as a new body starts: a body
 * left asleep by an episode would otherwise start the next one asleep. */
void evo_body_wake(evo_world *w, evo_body_id id) EVO_WORLD_NOEXCEPT;

/* Weld b to a where they are now (they then stop colliding with each
 * other): the claw's grip. Returns a joint id >= 0, or -1 (not two
 * bodies of w, or out of memory). Removing a
 * body removes its welds first with evo_world_unweld. */
int evo_world_weld(evo_world *w, evo_body_id a,
		   evo_body_id b) EVO_WORLD_NOEXCEPT;
void evo_world_unweld(evo_world *w, int joint) EVO_WORLD_NOEXCEPT;

/* The nearest hit along the segment p1 -> p2 among shapes whose category
 * is in mask, ignoring the body `ignore`: fraction of the segment in
 * [0, 1], or -1 when nothing is hit. */
double evo_world_raycast(const evo_world *w, double x1, double y1, double x2,
			 double y2, uint16_t mask,
			 evo_body_id ignore) EVO_WORLD_NOEXCEPT;

/* The shapes whose bounding boxes overlap the box [x0, x1] x [y0, y1],
 * in Box2D's order; writes at most cap and returns how many there are. */
int evo_world_query(const evo_world *w, double x0, double y0, double x1,
		    double y1, uint16_t mask, evo_shape_info *out,
		    int cap) EVO_WORLD_NOEXCEPT;

#ifdef __cplusplus
}
#endif

#endif
