"""python-can on the other end of evo's slcan pseudo-terminal: the
independent CAN peer of tests/sim/remote/test_can_peer.c.

usage: can_peer.py PTY

Opens PTY with python-can's own slcan interface (which closes the adapter,
sets its bit rate and opens it, as it would a CANable), sends one frame
evo must receive (0x123: 01 02 03), then waits for one frame from evo and
prints it as "got ID#DATA"; exits 0, or 1 when nothing came in 10 s.
"""
import sys

import can


def main():
    bus = can.Bus(interface="slcan", channel=sys.argv[1], bitrate=500000,
                  sleep_after_open=0.1)
    try:
        bus.send(can.Message(arbitration_id=0x123, is_extended_id=False,
                             data=[1, 2, 3]))
        msg = bus.recv(timeout=10)
        if msg is None:
            print("nothing from evo in 10 s")
            return 1
        print("got %03X#%s" % (msg.arbitration_id, msg.data.hex().upper()),
              flush=True)
        return 0
    finally:
        bus.shutdown()


if __name__ == "__main__":
    sys.exit(main())
