/* evo — where a piece of either world is, as its structs spell it
 * (sim/scene/element.h, bot.h, sensor.h, actuator.h): a position of three
 * numbers read as pos[] or as x, y, z (a 2D piece leaves z 0), and a turn
 * about the frame's third axis read as angle (2D's name) or yaw (3D's),
 * the same number in the frame's own sense. Each is an anonymous union,
 * a member of the struct that names it. */
#ifndef EVO_SCENE_PLACE_H
#define EVO_SCENE_PLACE_H

#define EVO_POSITION                                                           \
	union {                                                                \
		double pos[3];                                                 \
		struct {                                                       \
			double x, y, z;                                        \
		};                                                             \
	}

#define EVO_TURN                                                               \
	union {                                                                \
		double angle;                                                  \
		double yaw;                                                    \
	}

#endif
