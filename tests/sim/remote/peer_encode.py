"""The remote protocol's messages as the Python classes of lcm-gen encode
them, for tests/sim/remote/test_corridor.c: one line per message, its
name and its bytes in hex. The C test encodes the same fields with evo's
own encoders (sim/remote/wire.h) and compares, byte for byte.

Run with build/venv/bin/python and PYTHONPATH=build/gen/python."""

import evo_lcm


def hello(kind, session, url, envs, tick_us, sensors, actuators, name):
    m = evo_lcm.hello_t()
    m.protocol = evo_lcm.hello_t.PROTOCOL
    m.name, m.session, m.url, m.kind = name, session, url, kind
    m.environments, m.tick_us = envs, tick_us
    m.n_sensors, m.sensors = len(sensors), sensors
    m.n_actuators, m.actuators = len(actuators), actuators
    return m


def who(sender):
    m = evo_lcm.who_t()
    m.protocol = evo_lcm.hello_t.PROTOCOL
    m.sender = sender
    return m


def control(name, session, env, op, episode, layout_seed, seed):
    m = evo_lcm.control_t()
    m.name, m.session, m.env, m.op = name, session, env, op
    m.episode, m.layout_seed, m.seed = episode, layout_seed, seed
    return m


def sensors(name, session, env, episode, tick, values, reward, done):
    m = evo_lcm.sensors_t()
    m.name, m.session, m.env = name, session, env
    m.episode, m.tick = episode, tick
    m.n, m.values = len(values), values
    m.reward, m.done = reward, done
    return m


def command(name, session, env, episode, tick, values):
    m = evo_lcm.command_t()
    m.name, m.session, m.env = name, session, env
    m.episode, m.tick = episode, tick
    m.n, m.values = len(values), values
    return m


# The same fields as test_corridor.c's. LCM's int64 is signed: evo's
# unsigned seeds 2^64 - 1 and 2^63 are -1 and -2^63 here.
MESSAGES = [
    ("hello_sim", hello(evo_lcm.hello_t.SIMULATOR, 2**63 - 1,
                        "udpm://239.255.76.67:9568?ttl=0", 64, 0,
                        ["P1", "P2", "P3", "P4", "P5", "GB", "GD"],
                        ["MotL", "MotR"], "corridor-test_1")),
    ("hello_robot", hello(evo_lcm.hello_t.ROBOT, 1, "", 1, 20000,
                          ["S1"], [], "r")),
    ("who", who("evo-4242")),
    ("who_empty", who("")),
    ("control_reset", control("c", 123456789012345, 63,
                              evo_lcm.control_t.RESET, 2**53 + 1, -1,
                              -2**63)),
    ("control_stop", control("corridor", 7, 0, evo_lcm.control_t.STOP,
                             0, 0, 0)),
    ("sensors", sensors("corridor", 99, 3, 2, 399,
                        [0.0, 1.0, 0.1, 1 / 3, 5e-324, 0.5,
                         0.9999999999999999], -12.345678901234567, True)),
    ("sensors_none", sensors("x", -5, 0, 1, 0, [], -0.0, False)),
    ("command", command("corridor", 99, 3, 2, 399, [0.25, 0.75])),
]

for label, m in MESSAGES:
    data = m.encode()
    # and the class reads its own bytes back to the same bytes
    assert type(m).decode(data).encode() == data, label
    print(label, data.hex())
