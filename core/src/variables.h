/* Private: the variables' rules (docs/mind.md, "Variables"). */
#ifndef EVO_VARIABLES_H
#define EVO_VARIABLES_H

#include "evo/mind.h"

/* The state a variable of this type has at tick 0. */
void evo_var_reset(unsigned type, evo_var_state *v);

/* End of a tick: written says whether any skill wrote the variable this
 * tick, w is the influence-weighted mean of what they wrote. Moves value to
 * prev (for VD at the next tick) and computes the new value. */
void evo_var_update(unsigned type, evo_var_state *v, int written, evo_q16 w);

/* sin(2*pi*phase/2^32) mapped to [0, 1] as (sin + 1) / 2, in Q16. */
evo_q16 evo_var_sin01(uint32_t phase);

/* Phase step per tick, in 2^-32 turns: one radian, and the frequency a
 * written value w selects, from 1/1000 rad (w = 0) to 3 rad (w = 1). */
#define EVO_VAR_RADIAN_TURNS 683565276u /* round(2^32 / (2 * pi)) */
uint32_t evo_var_sin_step(evo_q16 w);

#endif
