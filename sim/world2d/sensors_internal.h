/* evo — private to the 2D sensors (sensors.c, proximity.c, sense_cells.c):
 * the bot's frame, boxes in the world and the set of shapes around a bot
 * that its proximity sensors and bumpers read, and the functions the three
 * files call in one another. */
#ifndef EVO_SENSORS_INTERNAL_H
#define EVO_SENSORS_INTERNAL_H

#include <math.h>
#include <stdint.h>

#include "world2d/scene.h"

/* Shapes kept on the stack for one query; a crowd larger than this goes
 * to the heap. */
#define QUERY_CAP 64

/* The bot's pose, with its rotation worked out once for every sensor. */
typedef struct sense_frame {
	double x, y, c, s;
} sense_frame;

/* What a bot's proximity rays can hit this tick. For a box, `radius`
 * holds its bounding radius, which the culling uses. */
typedef struct shape_set {
	evo_shape_info *s;
	int n;
	evo_shape_info local[QUERY_CAP];
} shape_set;

/* An axis-aligned box in world coordinates. */
typedef struct sense_box {
	double x0, y0, x1, y1;
} sense_box;

static inline void box_add(sense_box *b, double x, double y)
{
	b->x0 = x < b->x0 ? x : b->x0;
	b->y0 = y < b->y0 ? y : b->y0;
	b->x1 = x > b->x1 ? x : b->x1;
	b->y1 = y > b->y1 ? y : b->y1;
}

/* A sample into [0, 1] by the one rule for sensor values (docs/mind.md,
 * "Sensor values"; core's evo_q16_from_sensor, which world2d does not
 * see): below 0 reads 0, above 1 reads 1, NaN reads 0.5, the neutral
 * value. No sensor's geometry gives NaN from the finite definitions the
 * scene accepts; a world whose bodies' positions overflowed could. */
static inline double clamp01(double v)
{
	if (v != v)
		return 0.5;
	if (v > 1)
		return 1;
	return v >= 0 ? v : 0;
}

static inline int same_body(evo_body_id a, evo_body_id b)
{
	return a.index == b.index && a.generation == b.generation;
}

static inline sense_frame sense_frame_of(const evo_bot *b)
{
	sense_frame f = {b->x, b->y, b->c, b->s};
	return f;
}

static inline void to_world(const sense_frame *f, double bx, double by,
			    double *wx, double *wy)
{
	*wx = f->x + f->c * bx - f->s * by;
	*wy = f->y + f->s * bx + f->c * by;
}

/* Gives a box or a wall its bounding radius, which only the culling uses
 * (evo_proximity_sample); a circle has its own. sqrt serves, without
 * hypot's guard against overflow, a third of the cost at world sizes. */
static inline void bound_radius(evo_shape_info *s)
{
	if (s->type != EVO_SHAPE_CIRCLE) {
		double ex = s->vx[0] - s->x, ey = s->vy[0] - s->y;
		s->radius = sqrt(ex * ex + ey * ey);
	}
}

/* A bot's rays never see its own body, nor an object one of its claws
 * holds: the object sits right before the claw and would blind every
 * forward sensor while carried. */
static inline int unseen(const evo_scene *sc, const evo_bot *b, evo_body_id id)
{
	if (id.index < 0)
		return 0;
	if (same_body(id, b->body))
		return 1;
	for (int i = 0; i < b->n_actuators; i++) {
		int held = b->actuator[i].held;
		if (b->actuator[i].def.kind == EVO_ACT_CLAW && held >= 0 &&
		    held < sc->n_elements &&
		    same_body(id, sc->element[held].body))
			return 1;
	}
	return 0;
}

/* ---- proximity.c ------------------------------------------------------ */

/* One area query for the box `area`, keeping what the bot's rays may see
 * into set; evo_shapes_release gives back what it took from the heap. */
void evo_shapes_gather(const evo_scene *sc, const evo_bot *b,
		       const sense_box *area, uint16_t mask, shape_set *set);
void evo_shapes_release(shape_set *set);
/* Adds what a proximity sensor's rays can reach to area. */
void evo_fan_box(const evo_sensor *se, const sense_frame *f, sense_box *area);
/* A proximity sensor's reading against the shapes of set; stores its
 * rays' hit fractions. */
double evo_proximity_sample(evo_sensor *se, const sense_frame *f,
			    const shape_set *set);
/* The box that holds every fan and bumper of a bot, and the union of what
 * they see (0: none reads anything). */
uint16_t evo_sense_area(const evo_bot *b, const sense_frame *f,
			sense_box *area);

/* ---- sensors.c -------------------------------------------------------- */

/* Every sensor of a bot that is not idle, with set the shapes around it. */
void evo_bot_sense_with(evo_scene *sc, int bot, const sense_frame *f,
			const shape_set *set);

#endif
