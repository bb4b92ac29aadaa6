/* evo — the whole public API of the core. */
#ifndef EVO_EVO_H
#define EVO_EVO_H

#include "evo/fixed.h"
#include "evo/formats.h"
#include "evo/image.h"
#include "evo/mind.h"
#include "evo/net.h"
#include "evo/status.h"

#endif
