/* evo — the sensors of a bot of either dimension (docs/architecture.md,
 * "Where the layout is going", step 4): one definition, `evo_sensor_def`,
 * and one sensor, `evo_sensor`, for the 2D scene (world2d/scene.h) and the
 * 3D one (world3d/scene3d.h), and the part of adding one that both worlds
 * share: the checks, the name and the stored copy (evo_sensor_store). What
 * is the world's stays in it: the directions of a proximity sensor's rays
 * and the masks of teams (world2d/scene.c, world3d/scene3d.c), and the
 * sampling, whose geometry is the world's (world2d/sensors.c,
 * proximity.c, sense_cells.c; world3d/sensors3d.c).
 *
 * The kind is scene/kinds.h's evo_sense_kind; which kinds each world has is
 * its row of kinds.c (3D's azimuth is the bearing sensor). Each field says
 * which world reads it. Where both worlds keep one quantity under two
 * names an anonymous union gives both spellings: x, y, z are pos[0..2]
 * (2D leaves z 0); 2D's angle is 3D's yaw (a turn about the frame's third
 * axis, in the frame's own sense).
 *
 * What each kind reads, in [0, 1] (booleans EVO_FALSE 0.2, EVO_TRUE 0.8):
 *   proximity   the nearest hit of its rays / range; 1 = clear
 *   distance    distance to target / scale, clamped
 *   zone        TRUE when the bot's centre is in the target zone
 *   bearing     0.5 + angle to target / 2 pi; 0.5 ahead (3D: azimuth,
 *               the tutorial's TargetSensor:1)
 *   elevation   3D: 0.5 + elevation / pi (TargetSensor:2)
 *   presence    2D: TRUE when the target exists (is active)
 *   object      2D: TRUE when a free object is within reach ahead
 *   movement    2D: spread of recent positions / scale, clamped
 *   random      uniform in [0, 1) from the scene's rng
 *   constant    value
 *   holding     2D: TRUE when the bot's claw holds an object
 *   radar       2D: TRUE when the target's bearing is within arc of angle
 *   bumper      2D: TRUE when an obstacle within reach lies within arc
 *   light, ground, range and bearing, camera: scene/swarm.h's
 *
 * Defaults are one function per world, both returning this struct, since
 * a sensor's default mask is made of its world's categories and the
 * worlds' scales differ (2D's rays reach 12 m, 3D's 3 m):
 * evo_default_sensor_def (world2d/scene.h) and evo_default_sensor3d_def
 * (world3d/scene3d.h). */
#ifndef EVO_SENSOR_H
#define EVO_SENSOR_H

#include <stdint.h>

#include "base/err.h"
#include "scene/kinds.h"
#include "scene/place.h"
#include "scene/store.h"
#include "scene/swarm.h"

/* The most rays a proximity sensor has, in either world. */
#define EVO_PROX_MAX_RAYS 32

typedef struct evo_sensor_def {
	evo_sense_kind kind; /* both: a kind of the world's (kinds.c) */
	const char *name;    /* both; may be NULL */
	/* both: where it sits in the bot's frame (2D: x, y; 3D: pos[]) */
	EVO_POSITION;
	/* both: which way it faces in the bot's frame (2D: angle, + to the
	 * bot's right; 3D: yaw, + to its left), radians */
	EVO_TURN;
	double pitch; /* 3D: up from the horizontal, radians */
	/* proximity, both: how far its rays reach (2D 12, 3D 3 m), the half
	 * angle of their fan (2D 6 degrees, 3D 0) and how many (2D 9, 3D 1),
	 * spread evenly over [-arc, +arc] */
	double range;
	double arc; /* 2D: also a bumper's and radar's half angle */
	int rays;
	double deadzone; /* 2D proximity: a reading below it is 0 (0.005) */
	/* proximity, both: what its rays see, the world's categories
	 * (2D: obstacles and bots; 3D: bots, obstacles and objects); 2D
	 * bumpers too */
	uint16_t mask;
	/* 2D: and the bots of the sensor's own team, of the others: made
	 * into mask bits when the sensor is added to a bot of a team */
	int sees_teammates, sees_opponents;
	/* both: what a distance, zone, bearing (2D: presence, radar; 3D:
	 * elevation) sensor looks at: an element, or one of
	 * scene/scoring.h's EVO_TARGET_* (3D: EVO_TARGET_NONE only) */
	int target;
	/* the distance that reads 1: both a distance sensor's (2D 100, 3D
	 * 20 m), 2D a movement sensor's (1.5) */
	double scale;
	/* 2D: an object detector's reach ahead of (x, y) along angle
	 * (1.5); a bumper's, how near the bot's centre a shape must come
	 * (1.05) */
	double reach;
	double value; /* both: a constant sensor's (0.5) */
	/* both: light (aperture), range and bearing (range: 2D 30, 3D 3;
	 * slot, read, index, occluded, scale), camera */
	evo_swarm_sensor swarm;
} evo_sensor_def;

typedef struct evo_sensor {
	char name[EVO_PIECE_NAME_MAX];
	evo_sensor_def def; /* both: as added (def.name NULL: name is it) */
	double value;	    /* both: the last sample, in [0, 1] */
	/* 2D: 1 when evo_bot_sense skips it, because nothing reads it
	 * (evo_sim sets this from the botdesc and the rewards);
	 * evo_sensor_sample still samples it */
	int idle;
	/* proximity, both: each ray's hit fraction of range in [0, 1] (1:
	 * nothing), for the viewer; rays past def.rays keep 1 */
	float ray[EVO_PROX_MAX_RAYS];
	/* proximity, both: each ray's unit direction in the bot's frame,
	 * worked out once when the sensor is added by its world:
	 * (ray_c[i], ray_s[i], ray_z). 2D: the cosine and sine of ray i's
	 * angle, ray_z 0; 3D: ray i's yaw's cosine and sine times the
	 * pitch's cosine, ray_z the pitch's sine (one pitch for the fan) */
	double ray_c[EVO_PROX_MAX_RAYS], ray_s[EVO_PROX_MAX_RAYS];
	double ray_z;
} evo_sensor;

/* Adding a sensor, both worlds' part: checks d for world dim (EVO_DIM_2D
 * or EVO_DIM_3D: a kind of that world by its row of kinds.c, numbers,
 * a proximity sensor's range, arc and rays, a scale, reach and arc where
 * the kind reads one, a swarm sensor's settings, a name not used by the
 * first n sensors of *arr) and stores it as sensor n of *arr (a bot's
 * sensors, which grow 8 at a time), named d->name or, unnamed, dflt and
 * its number ("sensor3"; "" when dflt is NULL), with every ray clear.
 * bot names the bot in the messages. The new sensor, or NULL with err
 * set; the caller works out what its world needs (rays' directions,
 * masks of teams) and counts it. */
evo_sensor *evo_sensor_store(evo_sensor **arr, int n, const evo_sensor_def *d,
			     unsigned dim, const char *bot, const char *dflt,
			     evo_err *err);

#endif
