/* evo — the actuators of the 2D world: wheels push the bot's body, claws
 * grab and let go of objects (docs/world.md). */
#ifndef EVO_ACTUATORS_H
#define EVO_ACTUATORS_H

#include "world2d/scene.h"

/* Act on the actuator's command for one step (before the
 * physics steps). */
void evo_actuator_act(evo_scene *sc, int bot, int actuator);
/* Set a bot's velocity from its speed wheels and drives, after each of
 * them acted (nothing for a bot with none): their forward speed along the
 * heading and their turn rate (docs/world.md). */
void evo_bot_drive(evo_scene *sc, int bot);
/* Open every claw of a bot (reset, delivery). */
void evo_bot_release(evo_scene *sc, int bot);

#endif
