/* evo — the swarm sensors, once for both worlds (issue 32, "Sensors and
 * robots for swarms"; docs/world.md, "Swarm sensors"): light sources and
 * light sensors, floor patches and ground sensors, range-and-bearing
 * messages between bots, and omnidirectional cameras that see coloured
 * blobs.
 *
 * What is here knows nothing of the world it runs in: a bot is a pose (a
 * position of three numbers and a turn R, world = pos + R body; a 2D
 * scene keeps z = 0 and turns about z only), the lights and patches are
 * the scene's evo_swarm, the other bots are asked for through a function,
 * and occlusion is the backend's raycast (sim/scene/backend.h). The 2D
 * and 3D scenes keep an evo_swarm each and call these where they sample
 * their sensors.
 *
 * Bearings are measured in the bot's horizontal plane, atan2 of the
 * thing's y over its x in the bot's frame: +y is the bot's right in 2D
 * (the screen's y grows downward) and its left in 3D, as each world's
 * bearing sensors already read. */
#ifndef EVO_SCENE_SWARM_H
#define EVO_SCENE_SWARM_H

#include "base/err.h"
#include "scene/backend.h"

/* neighbours a range-and-bearing sensor ranks, values one bot broadcasts */
#define EVO_SWARM_MAX_SLOTS  16
#define EVO_SWARM_MAX_VALUES 8

/* A light source: a point that shines `intensity` (the distance squared,
 * m^2, at which a light sensor facing it reads 1). */
typedef struct evo_light {
	double pos[3];
	double intensity;
} evo_light;

/* A patch of the floor: a rectangle (half sides hx, hy, turned by yaw)
 * or a circle (radius), of a grey level in [0, 1] (0 black, 1 white).
 * Patches lie on the ground: only x and y count. */
typedef struct evo_patch {
	int circle;
	double x, y, yaw;
	double hx, hy, radius;
	double grey;
} evo_patch;

/* The colours a camera tells apart, in the order of their readings: the
 * colour of number k reads (k + 1) / EVO_COLOUR_COUNT. */
typedef enum evo_colour {
	EVO_COLOUR_RED = 0,
	EVO_COLOUR_YELLOW,
	EVO_COLOUR_GREEN,
	EVO_COLOUR_CYAN,
	EVO_COLOUR_BLUE,
	EVO_COLOUR_MAGENTA,
	EVO_COLOUR_WHITE,
	EVO_COLOUR_BLACK,
	EVO_COLOUR_COUNT
} evo_colour;

/* A colour's name ("red") and the colour of a name, -1 when unknown. */
const char *evo_colour_name(int colour);
int evo_colour_by_name(const char *name);

/* What carries a colour a camera sees: a light, a bot or an element (of
 * the scene's own numbering). */
typedef enum evo_blob_kind {
	EVO_BLOB_LIGHT = 0,
	EVO_BLOB_BOT,
	EVO_BLOB_ELEMENT,
} evo_blob_kind;

typedef struct evo_blob {
	evo_blob_kind kind;
	int index;
	int colour; /* evo_colour */
} evo_blob;

/* The lights, patches and coloured blobs of a scene. The floor outside
 * every patch reads EVO_SWARM_FLOOR; of patches that overlap, the one
 * added last is on top. */
#define EVO_SWARM_FLOOR 1.0
typedef struct evo_swarm {
	int n_lights, cap_lights, n_patches, cap_patches, n_blobs, cap_blobs;
	evo_light *light;
	evo_patch *patch;
	evo_blob *blob;
} evo_swarm;

/* Add a light or a patch: its index, or -1 with err set (a value that is
 * not a number, an intensity or size not above 0, a grey level outside
 * [0, 1], out of memory). */
int evo_swarm_add_light(evo_swarm *w, const evo_light *l, evo_err *err);
int evo_swarm_add_patch(evo_swarm *w, const evo_patch *p, evo_err *err);
/* Give a light, bot or element a colour (a second call changes it): its
 * blob's index, or -1 with err set (an unknown colour, out of memory). */
int evo_swarm_set_colour(evo_swarm *w, evo_blob_kind kind, int index,
			 int colour, evo_err *err);
void evo_swarm_free(evo_swarm *w);

/* What a range-and-bearing sensor reads about the neighbour of its slot. */
typedef enum evo_rab_read {
	EVO_RAB_RANGE = 0, /* distance / range; 1 with no neighbour there */
	EVO_RAB_BEARING,   /* 0.5 + bearing / 2 pi; 0.5 with none */
	EVO_RAB_VALUE,	   /* its broadcast value `index`; 0 with none */
	EVO_RAB_COUNT,	   /* neighbours in range / scale, at most 1 */
	EVO_RAB_COLOUR,	   /* camera: its colour's reading; 0 with none */
	EVO_RAB_READ_COUNT
} evo_rab_read;

/* The settings of a swarm sensor, the same in both worlds. Where it sits
 * on the bot and which way it faces are the scene's sensor's own. */
typedef struct evo_swarm_sensor {
	double aperture; /* light: half angle about its axis, radians (pi/4) */
	double range;	 /* range and bearing: how far it hears, m (> 0) */
	int slot;	 /* range and bearing: 1 the nearest neighbour, 2 ... */
	evo_rab_read read;
	int index;    /* EVO_RAB_VALUE: which of the values, 0 based */
	int occluded; /* range and bearing: 1, obstacles stop messages */
	double scale; /* EVO_RAB_COUNT: the count that reads 1 */
	int colour;   /* camera: the only colour it sees; -1 any (default) */
} evo_swarm_sensor;

/* Aperture 45 degrees, slot 1, read range, scale 10; range (m) is each
 * world's own, as 2D worlds are tens of metres and 3D ones a few. */
evo_swarm_sensor evo_default_swarm_sensor(double range);

/* The sensor's settings checked: 0, or -1 with err set naming `name`. */
int evo_swarm_check_sensor(const evo_swarm_sensor *s, const char *name,
			   evo_err *err);

/* A bot's pose: world = pos + R body. */
typedef struct evo_swarm_frame {
	double pos[3];
	double R[9]; /* row-major */
} evo_swarm_frame;

/* An angle (radians) into (-pi, pi], for the bearings of the swarm
 * sensors here and of the 2D world's radar and bumper. */
double evo_wrap_angle(double a);

/* The frame of a 2D pose (z = 0, a turn by angle about z). */
evo_swarm_frame evo_swarm_frame_2d(double x, double y, double angle);

/* Occlusion: rays through the backend among `mask`, ignoring the bot's
 * own body (2D) or group (3D). NULL: nothing occludes. */
typedef struct evo_swarm_rays {
	const evo_backend *be;
	evo_bworld *bw;
	uint16_t mask;
	evo_body_id ignore;
	int ignore_group;
} evo_swarm_rays;

/* A light sensor at `at` (the bot's frame) facing `yaw` (about the bot's
 * z): the sum over the lights whose bearing lies within aperture of yaw
 * and whose straight line from the sensor no obstacle cuts of
 * min(1, intensity / d^2), d the distance from the sensor to the light;
 * the sum at most 1. */
double evo_swarm_light(const evo_swarm *w, const evo_swarm_frame *f,
		       const double at[3], double yaw, double aperture,
		       const evo_swarm_rays *rays);

/* A ground sensor at `at` (the bot's frame): the grey level of the top
 * patch under it, or EVO_SWARM_FLOOR. */
double evo_swarm_ground(const evo_swarm *w, const evo_swarm_frame *f,
			const double at[3]);

/* Another bot as a range-and-bearing sensor hears it: its centre and the
 * values it broadcasts (its broadcast actuators' commands, in [0, 1]). */
typedef struct evo_swarm_peer {
	double pos[3];
	int n_values;
	double value[EVO_SWARM_MAX_VALUES];
} evo_swarm_peer;

/* Fill *out for bot i; 0 when bot i broadcasts nothing (it has no
 * broadcast actuator: not heard), 1 when it does. */
typedef int (*evo_swarm_peer_fn)(void *ctx, int i, evo_swarm_peer *out);

/* A range-and-bearing sensor of bot `self` (frame f): of the n - 1 other
 * bots that broadcast, those whose centre lies within range of f's (and,
 * with occluded, in sight of it), ranked by distance (ties: the lower
 * index first); the reading of s->read about the one of rank s->slot. */
double evo_swarm_rab(const evo_swarm_sensor *s, const evo_swarm_frame *f,
		     int self, int n, evo_swarm_peer_fn peer, void *ctx,
		     const evo_swarm_rays *rays);

/* Where blob b is now (pos) and how far its body reaches from there
 * (*radius, 0 for a point or a body no ray of the camera hits); 0 when
 * it is out of the world (a delivered object). */
typedef int (*evo_swarm_where_fn)(void *ctx, const evo_blob *b, double pos[3],
				  double *radius);

/* An omnidirectional camera of bot `self` (frame f): the blobs (every
 * coloured light, bot but self, element) of s->colour (or any) whose
 * centre lies within range of f's, in sight of it with s->occluded (an
 * obstacle nearer than the blob's own reach hides it), ranked by
 * distance (ties: in the order they were coloured); the reading of
 * s->read (EVO_RAB_RANGE, _BEARING, _COLOUR or _COUNT) about the one of
 * rank s->slot. */
double evo_swarm_camera(const evo_swarm *w, const evo_swarm_sensor *s,
			const evo_swarm_frame *f, int self,
			evo_swarm_where_fn where, void *ctx,
			const evo_swarm_rays *rays);

#endif
