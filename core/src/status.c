#include "evo/status.h"

static const char *const messages[] = {
#define EVO_STATUS_TEXT(code, text) text,
	EVO_STATUS_LIST(EVO_STATUS_TEXT)
#undef EVO_STATUS_TEXT
};

const char *evo_status_str(evo_status s)
{
	if ((unsigned)s >= EVO_STATUS_COUNT)
		return "unknown status";
	return messages[s];
}
