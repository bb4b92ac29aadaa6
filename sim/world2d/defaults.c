/* The defaults every Def of the 2D world starts from (sim/world2d/scene.h):
 * EvoAgents' values, so a bot model or environment that leaves a field
 * out gets what the tutorial's did. An element's are the scene model's
 * (scene/element.c, evo_default_element_def). */
#include <math.h>
#include <string.h>

#include "world2d/scene.h"

evo_grid_def evo_default_grid_def(void)
{
	evo_grid_def g;
	memset(&g, 0, sizeof g);
	g.x0 = g.y0 = -100;
	g.x1 = g.y1 = 100;
	g.spacing = 18.0;
	g.min_size = 1.0;
	g.size_variability = 2.0;
	g.clearance = 3.0;
	return g;
}

evo_sensor_def evo_default_sensor_def(evo_sense_kind kind)
{
	evo_sensor_def d;
	memset(&d, 0, sizeof d);
	d.kind = kind;
	d.range = 12.0;
	d.arc = 6.0 * M_PI / 180.0;
	d.rays = 9;
	d.deadzone = 0.005;
	d.mask = EVO_CAT_OBSTACLE | EVO_CAT_BOT;
	d.target = EVO_TARGET_NONE;
	d.scale = kind == EVO_SENSE_MOVEMENT ? 1.5 : 100.0;
	d.reach = 1.5;
	if (kind == EVO_SENSE_OBJECT_DETECTOR || kind == EVO_SENSE_RADAR ||
	    kind == EVO_SENSE_BUMPER) {
		d.x = kind == EVO_SENSE_OBJECT_DETECTOR ? 1.0 : 0.0;
		d.arc = 45.0 * M_PI / 180.0;
	}
	if (kind == EVO_SENSE_BUMPER)
		d.reach = 1.05;
	d.value = 0.5;
	d.swarm = evo_default_swarm_sensor(30.0); /* BotType8's: 2 m wide */
	return d;
}

evo_bot_def evo_default_bot_def(void)
{
	evo_bot_def d;
	memset(&d, 0, sizeof d);
	d.body.dynamic = 1;
	d.body.n_shapes = 1;
	d.body.shape[0].type = EVO_SHAPE_CIRCLE;
	d.body.shape[0].radius = 1.0;
	d.body.shape[0].half[0] = d.body.shape[0].half[1] = 1.0;
	d.body.shape[0].friction = 0.0;
	d.body.density = 2.0;
	d.body.linear_damping = 5.0;
	d.body.angular_damping = 20.0;
	d.body.allow_sleep = 0;
	d.body.category = EVO_CAT_BOT;
	d.body.mask = EVO_CAT_ALL;
	d.body.group = -1;
	d.team = -1;
	return d;
}

