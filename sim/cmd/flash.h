/* `evo flash MINDFOLDER --can URL`: send a mind image to a running robot's
 * firmware over CAN (core's evo/flash.h over remote/can.h), which switches
 * to it between two ticks or refuses it with a reason and keeps its mind
 * (docs/firmware.md, "Sending a mind"; the frames in docs/wire.md). */
#ifndef EVO_CMD_FLASH_H
#define EVO_CMD_FLASH_H

#include <stdio.h>

/* argv[1] is "flash". Returns the process exit status: 0 when the robot
 * runs the new mind, 1 when it refused it or stopped answering (it then
 * runs the mind it had), 2 for a wrong command line. */
int evo_flash_main(int argc, char **argv);

/* What `evo flash --help` prints. */
void evo_flash_usage(FILE *f);

#endif
