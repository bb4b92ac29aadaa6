/* The robot this firmware drives: BotType8 with the Collect mind folder's
 * sensors, actuators and variables, in botdesc and vardesc order. A mind
 * image runs only if it was built for exactly these names (its names
 * hash); change this file with the robot, not with the mind. */
#define FW_BOT_NAME "Collect"
#define FW_BOT_SENSORS                                                         \
	"S1", "S2", "S3", "S4", "S5", "S6", "S7", "S8", "S9", "S10", "DOF",    \
		"ACTOBJ", "DISTOBJ", "RADOBJ", "SENSOBJ", "ACTDZ", "DISTDZ",   \
		"RADDZ", "SENSDZ", "RANDOM",
#define FW_BOT_ACTUATORS "MotL", "MotR", "EMAG",
#define FW_BOT_VARIABLES "HOLD",
