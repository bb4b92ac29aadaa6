/* Small scenes for the tests of sim/: a bot, elements placed by hand. */
#ifndef EVO_TEST_SCENES_H
#define EVO_TEST_SCENES_H

#include "world2d/scene.h"

/* A scene with one BotType8-like bot (evo_default_bot_def) named "bot"
 * at (x, y) heading `angle` radians. */
evo_scene *scene_with_bot(double x, double y, double angle);

/* A cylinder, zone or object (size: radius or half side) at (x, y); a box
 * of half sides hw x hh turned by `angle`. The element's index, or -1. */
int scene_add_element(evo_scene *sc, evo_piece_kind kind, double x,
		      double y, double size);
int scene_add_box(evo_scene *sc, double x, double y, double hw, double hh,
		  double angle);

#endif
