/* Small scenes for the tests of sim/ (tests/support/scenes.h). */
#include "scenes.h"

evo_scene *scene_with_bot(double x, double y, double angle)
{
	evo_scene *sc = evo_scene_create();
	evo_bot_def b = evo_default_bot_def();
	b.name = "bot";
	b.x = x;
	b.y = y;
	b.yaw = angle;
	evo_scene_add_bot(sc, &b);
	return sc;
}

int scene_add_element(evo_scene *sc, evo_piece_kind kind, double x,
		      double y, double size)
{
	evo_element_def e = evo_default_element_def(kind, EVO_DIM_2D);
	e.x = x;
	e.y = y;
	e.size = size;
	return evo_scene_add_element(sc, &e);
}

int scene_add_box(evo_scene *sc, double x, double y, double hw, double hh,
		  double angle)
{
	evo_element_def e = evo_default_element_def(EVO_PIECE_BOX, EVO_DIM_2D);
	e.x = x;
	e.y = y;
	e.half_w = hw;
	e.half_h = hh;
	e.angle = angle;
	return evo_scene_add_element(sc, &e);
}
