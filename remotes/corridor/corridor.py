#!/usr/bin/env python3
"""corridor.py: a remote simulator for evo, written in Python.

A disc robot with two wheels drives down a corridor, around a few posts,
to a goal at the far end. The world and its physics are this file's own;
evo runs the mind and drives the world over LCM in lockstep, by the
protocol of docs/remote.md, with the message classes lcm-gen makes from
lcmtypes/evo_remote.lcm (`make` writes them into build/gen/python).

    build/venv/bin/python remotes/corridor/corridor.py --name corridor

The robot's sensors, each in [0, 1]:
    P1..P5  proximity rays at 90 and 45 degrees left, ahead, 45 and 90
            degrees right: 1.0 nothing within 1 m of the rim, 0.0 touching
    GB      the goal's bearing: 0.5 straight ahead, above 0.5 to the right
            (0.75: 90 degrees right), 0 or 1 behind
    GD      the distance to the goal's centre over the corridor's length
and its actuators, MotL and MotR: wheel speeds, 0.5 standing, 1.0 full
ahead, 0.0 full back (evo's convention).

Reward per tick: 10 per metre the robot comes closer to the goal's
centre (negative when it goes away), -0.1 for each tick it touches a
wall or a post, and 10 when it reaches the goal, which ends the episode
(done). The layout (where the posts and the goal are) comes from the
RESET's layout_seed; the start pose and the wheels' noise from its seed:
the same seeds give the same episode, tick for tick.
"""

import argparse
import hashlib
import hmac
import math
import os
import random
import select
import signal
import struct
import sys
import time

PROTOCOL = 2
MAX_ENVIRONMENTS = 64  # evo's EVO_REMOTE_MAX_ENVS
LATE_RESET_S = 2.0  # the same RESET past tick 0 within it: a late copy

SENSORS = ["P1", "P2", "P3", "P4", "P5", "GB", "GD"]
ACTUATORS = ["MotL", "MotR"]

# ---- the world ---------------------------------------------------------------

LENGTH = 8.0  # m, along x; the robot starts near x = 0
WIDTH = 2.0  # m, y from -1 to 1
ROBOT_R = 0.15  # m, the robot's radius
AXLE = 0.3  # m, between the wheels
V_MAX = 0.5  # m/s, a wheel at command 1.0
DT = 0.1  # s per tick
RAY_RANGE = 1.0  # m from the rim
RAY_ANGLES = [90, 45, 0, -45, -90]  # degrees, counterclockwise from ahead
WHEEL_NOISE = 0.03  # standard deviation, relative to the wheel's speed
GOAL_R = 0.4
POST_R = 0.2
N_POSTS = 3
PROGRESS_REWARD = 10.0  # per metre closer to the goal
TOUCH_PENALTY = 0.1  # per tick touching
GOAL_REWARD = 10.0


def unsigned(seed):
    """The seed as the 64-bit unsigned number evo drew (LCM carries it as
    int64): random.Random(n) would take -n and n for the same seed."""
    return seed & 0xFFFFFFFFFFFFFFFF


class Corridor:
    """One world: the corridor, its posts and goal, and the robot."""

    def __init__(self, layout_seed, seed):
        lay = random.Random(unsigned(layout_seed))
        # posts spread along the corridor, each leaving at least 0.6 m on
        # one side
        self.posts = []
        for i in range(N_POSTS):
            x = 2.2 + i * 1.6 + lay.uniform(-0.4, 0.4)
            y = lay.uniform(-0.6, 0.6)
            self.posts.append((x, y))
        self.goal = (LENGTH - 0.7, lay.uniform(-0.5, 0.5))
        self.rng = random.Random(unsigned(seed))
        self.x = self.rng.uniform(0.4, 1.0)
        self.y = self.rng.uniform(-0.5, 0.5)
        self.heading = math.radians(self.rng.uniform(-60, 60))
        self.distance = self.goal_distance()
        self.touching = False

    def goal_distance(self):
        return math.hypot(self.goal[0] - self.x, self.goal[1] - self.y)

    def ray(self, angle):
        """Distance from the robot's centre along angle (world frame) to
        the first wall or post, at most ROBOT_R + RAY_RANGE."""
        dx, dy = math.cos(angle), math.sin(angle)
        best = ROBOT_R + RAY_RANGE
        # the four walls: y = +-WIDTH/2, x = 0, x = LENGTH
        if dy > 1e-12:
            best = min(best, (WIDTH / 2 - self.y) / dy)
        elif dy < -1e-12:
            best = min(best, (-WIDTH / 2 - self.y) / dy)
        if dx > 1e-12:
            best = min(best, (LENGTH - self.x) / dx)
        elif dx < -1e-12:
            best = min(best, -self.x / dx)
        for px, py in self.posts:
            # |p + t d - c| = R: t^2 - 2 t (d.(c - p)) + |c - p|^2 - R^2 = 0
            cx, cy = px - self.x, py - self.y
            b = dx * cx + dy * cy
            c = cx * cx + cy * cy - POST_R * POST_R
            disc = b * b - c
            if disc < 0:
                continue
            t = b - math.sqrt(disc)
            if t >= 0:
                best = min(best, t)
        return max(best, 0.0)

    def sense(self):
        values = []
        for a in RAY_ANGLES:
            d = self.ray(self.heading + math.radians(a)) - ROBOT_R
            values.append(min(max(d / RAY_RANGE, 0.0), 1.0))
        gx, gy = self.goal[0] - self.x, self.goal[1] - self.y
        # clockwise from ahead, in (-pi, pi]
        bearing = -(math.atan2(gy, gx) - self.heading)
        bearing = math.atan2(math.sin(bearing), math.cos(bearing))
        values.append(min(max(0.5 + bearing / (2 * math.pi), 0.0), 1.0))
        values.append(min(self.goal_distance() / LENGTH, 1.0))
        return values

    def collide(self):
        """Push the robot out of the walls and posts: True when it
        touched any."""
        touched = False
        for _ in range(3):
            moved = False
            lo, hi = -WIDTH / 2 + ROBOT_R, WIDTH / 2 - ROBOT_R
            if self.y < lo or self.y > hi:
                self.y = min(max(self.y, lo), hi)
                moved = True
            if self.x < ROBOT_R or self.x > LENGTH - ROBOT_R:
                self.x = min(max(self.x, ROBOT_R), LENGTH - ROBOT_R)
                moved = True
            for px, py in self.posts:
                dx, dy = self.x - px, self.y - py
                d = math.hypot(dx, dy)
                if d < ROBOT_R + POST_R:
                    if d < 1e-9:
                        dx, dy, d = -1.0, 0.0, 1.0
                    k = (ROBOT_R + POST_R) / d
                    self.x, self.y = px + dx * k, py + dy * k
                    moved = True
            touched = touched or moved
            if not moved:
                break
        # resting against a wall counts as touching it too
        eps = 1e-9
        if (abs(self.y) >= WIDTH / 2 - ROBOT_R - eps or
                self.x <= ROBOT_R + eps or self.x >= LENGTH - ROBOT_R - eps):
            touched = True
        for px, py in self.posts:
            if math.hypot(self.x - px, self.y - py) <= ROBOT_R + POST_R + eps:
                touched = True
        return touched

    def step(self, mot_l, mot_r):
        """One tick of DT with the wheel commands in [0, 1]: the tick's
        reward and whether the goal is reached."""
        vl = (2 * mot_l - 1) * V_MAX * (1 + self.rng.gauss(0, WHEEL_NOISE))
        vr = (2 * mot_r - 1) * V_MAX * (1 + self.rng.gauss(0, WHEEL_NOISE))
        v, w = (vl + vr) / 2, (vr - vl) / AXLE
        mid = self.heading + w * DT / 2
        self.x += v * math.cos(mid) * DT
        self.y += v * math.sin(mid) * DT
        self.heading = math.atan2(math.sin(self.heading + w * DT),
                                  math.cos(self.heading + w * DT))
        self.touching = self.collide()
        d = self.goal_distance()
        reward = PROGRESS_REWARD * (self.distance - d)
        self.distance = d
        if self.touching:
            reward -= TOUCH_PENALTY
        reached = d < GOAL_R
        if reached:
            reward += GOAL_REWARD
        return reward, reached


# ---- the protocol (docs/remote.md) --------------------------------------------

REASONS = ["undecodable", "foreign", "counts", "value", "stale", "ahead",
           "forged", "replayed"]

# The seal of docs/remote.md, Keys: after a message's bytes, an 8-byte
# big-endian stamp (microseconds of the real-time clock, strictly
# increasing) and HMAC-SHA-256 over the channel, a NUL, the bytes and the
# stamp.
SEAL_BYTES = 8 + 32
FRESH_US = 30000000
KEY_MIN, KEY_MAX = 16, 256


def read_key(path):
    """The key in a key file: its bytes without a trailing newline."""
    with open(path, "rb") as f:
        k = f.read(KEY_MAX + 3)
    if k.endswith(b"\n"):
        k = k[:-1]
    if k.endswith(b"\r"):
        k = k[:-1]
    if not KEY_MIN <= len(k) <= KEY_MAX:
        raise ValueError("key file %s: a key is %d to %d bytes" %
                         (path, KEY_MIN, KEY_MAX))
    return k


def mac(key, channel, body, stamp8):
    return hmac.new(key, channel.encode() + b"\0" + body + stamp8,
                    hashlib.sha256).digest()


class Env:
    """One environment: its world and where its episode is."""

    def __init__(self):
        self.world = None
        self.episode = 0  # 0: none yet
        self.seeds = (0, 0)
        self.reset_at = None  # when the episode's RESET came (monotonic)
        self.tick = 0  # the tick of the last sensors_t sent
        self.active = False
        self.reward = 0.0
        self.last = None  # that sensors_t's bytes


class Simulator:
    """lc: the LCM of the hello's URL (who_t, hello_t); data: that of the
    episodes' (control_t, sensors_t, command_t), which may be the same."""

    def __init__(self, lc, data, data_url, types, name, environments, log,
                 key=None):
        self.lc, self.data, self.t = lc, data, types
        self.key = key
        self.last_stamp = 0
        self.fresh = {}  # channel: the last stamp taken on it
        self.name = name
        self.session = int.from_bytes(os.urandom(8), "big") >> 1
        self.envs = [Env() for _ in range(environments)]
        self.log = log
        self.dropped = dict((r, 0) for r in REASONS)
        self.ch_control = "EVO_%s_CONTROL" % name
        self.ch_command = "EVO_%s_COMMAND" % name
        self.ch_sensors = "EVO_%s_SENSORS" % name
        h = types.hello_t()
        h.protocol = PROTOCOL
        h.name = name
        h.session = self.session
        h.url = data_url if data is not lc else ""
        h.kind = types.hello_t.SIMULATOR
        h.environments = environments
        h.tick_us = 0
        h.n_sensors, h.sensors = len(SENSORS), list(SENSORS)
        h.n_actuators, h.actuators = len(ACTUATORS), list(ACTUATORS)
        self.hello = h.encode()
        lc.subscribe("EVO_WHO", self.on_who)
        data.subscribe(self.ch_control, self.on_control)
        data.subscribe(self.ch_command, self.on_command)

    def drop(self, reason, what, why):
        if self.dropped[reason] == 0:
            print("corridor: dropped a %s (%s: %s); later drops are counted "
                  "and reported at the end" % (what, reason, why),
                  file=sys.stderr, flush=True)
        self.dropped[reason] += 1

    def decode(self, cls, data):
        """The message, or None (dropped as undecodable): lcm-gen's Python
        raises on bytes of another type or cut short, and this also refuses
        what it would pass over: bytes after the message."""
        try:
            buf = _Reader(data)
            m = cls.decode(buf)
            if buf.left():
                raise ValueError("%d bytes after the message" % buf.left())
            return m
        except (ValueError, struct.error, UnicodeDecodeError,
                MemoryError, OverflowError) as e:
            self.drop("undecodable", cls.__name__,
                      "not an evo_lcm.%s (%s)" % (cls.__name__, e))
            return None

    def ours(self, m, what):
        if (m.name == self.name and m.session == self.session and
                0 <= m.env < len(self.envs)):
            return True
        self.drop("foreign", what, "for %s, session %d, environment %d" %
                  (m.name, m.session, m.env))
        return False

    def publish(self, lc, channel, body):
        """Publish body on channel, sealed afresh when there is a key (a
        message sent again gets a new stamp)."""
        if self.key:
            stamp = max(time.time_ns() // 1000, self.last_stamp + 1)
            self.last_stamp = stamp
            stamp8 = stamp.to_bytes(8, "big", signed=True)
            body = body + stamp8 + mac(self.key, channel, body, stamp8)
        lc.publish(channel, body)

    def unseal(self, channel, data, what, ordered):
        """The message's bytes without their seal, or None (dropped as
        forged or replayed). ordered: its stamp must be newer than the
        last taken on the channel."""
        if not self.key:
            return data
        if len(data) < 8 + SEAL_BYTES:
            self.drop("forged", what, "%d bytes, too few for a seal" %
                      len(data))
            return None
        body, stamp8, tag = data[:-SEAL_BYTES], data[-SEAL_BYTES:-32], \
            data[-32:]
        if not hmac.compare_digest(tag, mac(self.key, channel, body, stamp8)):
            self.drop("forged", what, "its MAC fails the key")
            return None
        stamp = int.from_bytes(stamp8, "big", signed=True)
        if abs(stamp - time.time_ns() // 1000) > FRESH_US:
            self.drop("replayed", what, "stamped %.0f s from this clock" %
                      (abs(stamp - time.time_ns() // 1000) * 1e-6))
            return None
        if ordered:
            if stamp <= self.fresh.get(channel, 0):
                self.drop("replayed", what, "not newer than the last taken")
                return None
            self.fresh[channel] = stamp
        return body

    def publish_hello(self):
        self.publish(self.lc, "EVO_HELLO", self.hello)

    def send_sensors(self, env, e, done):
        s = self.t.sensors_t()
        s.name, s.session, s.env = self.name, self.session, env
        s.episode, s.tick = e.episode, e.tick
        s.values = e.world.sense()
        s.n = len(s.values)
        s.reward, s.done = e.reward, done
        # what the episode did so far, for novelty search and MAP-Elites:
        # where the robot is, scaled into the corridor, each in [0, 1]
        w = e.world
        s.behaviour = [min(1.0, max(0.0, w.x / LENGTH)),
                       min(1.0, max(0.0, (w.y + WIDTH / 2) / WIDTH))]
        s.n_behaviour = len(s.behaviour)
        e.last = s.encode()
        self.publish(self.data, self.ch_sensors, e.last)

    def end(self, env, e, how):
        """An episode is over: its line in the log."""
        e.active = False
        if self.log:
            self.log.write("env %d episode %d (layout_seed %d, seed %d): "
                           "reward %.6f over %d ticks, %s\n" %
                           (env, e.episode, unsigned(e.seeds[0]),
                            unsigned(e.seeds[1]), e.reward, e.tick, how))
            self.log.flush()

    def on_who(self, channel, data):
        data = self.unseal(channel, data, "who_t", False)
        if data is not None and self.decode(self.t.who_t, data):
            self.publish_hello()

    def on_control(self, channel, data):
        data = self.unseal(channel, data, "control_t", True)
        c = data is not None and self.decode(self.t.control_t, data)
        if not c or not self.ours(c, "control_t"):
            return
        e = self.envs[c.env]
        if c.op == self.t.control_t.STOP:
            if e.active:
                self.end(c.env, e, "stopped")
            e.reset_at = None  # the same RESET after it starts over
            return
        if c.op != self.t.control_t.RESET:
            self.drop("value", "control_t", "op %d" % c.op)
            return
        # the RESET of the episode still at tick 0, with the same seeds,
        # again: its answer was lost, so it goes again, and the world stays
        # as it is
        if (e.active and c.episode == e.episode and e.tick == 0 and
                (c.layout_seed, c.seed) == e.seeds):
            self.publish(self.data, self.ch_sensors, e.last)
            return
        # the same RESET past tick 0, soon after it: a copy evo sent again
        # while the first answer was on its way, come late; starting over
        # would leave evo's next command ahead of the world
        now = time.monotonic()
        if (e.tick > 0 and c.episode == e.episode and
                (c.layout_seed, c.seed) == e.seeds and
                e.reset_at is not None and now - e.reset_at < LATE_RESET_S):
            self.drop("stale", "control_t",
                      "a late copy of the RESET of episode %d, now at tick %d"
                      % (c.episode, e.tick))
            return
        if c.episode < 1:
            self.drop("value", "control_t", "episode %d" % c.episode)
            return
        if e.active:
            self.end(c.env, e, "cut short by a new RESET")
        e.world = Corridor(c.layout_seed, c.seed)
        e.episode, e.seeds = c.episode, (c.layout_seed, c.seed)
        e.tick, e.reward, e.active = 0, 0.0, True
        e.reset_at = now
        self.send_sensors(c.env, e, False)

    def on_command(self, channel, data):
        data = self.unseal(channel, data, "command_t", True)
        c = data is not None and self.decode(self.t.command_t, data)
        if not c or not self.ours(c, "command_t"):
            return
        e = self.envs[c.env]
        if c.n != len(ACTUATORS):
            self.drop("counts", "command_t", "%d values; the hello says %d" %
                      (c.n, len(ACTUATORS)))
            return
        # the command answered last, again (even the one that ended the
        # episode): its answer was lost, so it goes again, without a step
        if (e.last is not None and c.episode == e.episode and
                c.tick == e.tick - 1):
            self.publish(self.data, self.ch_sensors, e.last)
            return
        if not e.active or c.episode != e.episode or c.tick != e.tick:
            ahead = (c.episode > e.episode or
                     (c.episode == e.episode and c.tick > e.tick))
            self.drop("ahead" if ahead else "stale", "command_t",
                      "tick %d of episode %d; this environment is at tick %d "
                      "of episode %d%s" % (c.tick, c.episode, e.tick,
                                           e.episode,
                                           "" if e.active else " (ended)"))
            return
        for i, v in enumerate(c.values):
            if not (0.0 <= v <= 1.0):  # also NaN
                self.drop("value", "command_t", "%s = %r" % (ACTUATORS[i], v))
                return
        reward, reached = e.world.step(c.values[0], c.values[1])
        e.reward += reward
        e.tick += 1
        if reached:
            self.end(c.env, e, "goal")
        self.send_sensors(c.env, e, reached)

    def close(self):
        for i, e in enumerate(self.envs):
            if e.active:
                self.end(i, e, "open when the simulator stopped")
        total = sum(self.dropped.values())
        if total:
            print("corridor: dropped %d message%s (%s)" % (
                total, "" if total == 1 else "s",
                ", ".join("%d %s" % (self.dropped[r], r) for r in REASONS
                          if self.dropped[r])), file=sys.stderr)


class _Reader:
    """The bytes of a message, read as lcm-gen's decoders read a file; a
    read past the end raises instead of returning fewer bytes."""

    def __init__(self, data):
        self.data, self.pos = data, 0

    def read(self, n):
        if n < 0 or self.pos + n > len(self.data):
            raise ValueError("cut short")
        b = self.data[self.pos:self.pos + n]
        self.pos += n
        return b

    def left(self):
        return len(self.data) - self.pos


# ---- the program ---------------------------------------------------------------

def import_types():
    """lcm (from PyPI: build/venv after `make deps`) and evo_lcm (made by
    lcm-gen: build/gen/python after `make`), from PYTHONPATH or else this
    repository's build/."""
    try:
        import lcm
    except ImportError:
        sys.exit("corridor.py: no `lcm` module: run it with build/venv/bin/"
                 "python (`make deps` makes it)")
    try:
        import evo_lcm
    except ImportError:
        root = os.path.dirname(os.path.dirname(os.path.dirname(
            os.path.abspath(__file__))))
        sys.path.insert(0, os.path.join(root, "build", "gen", "python"))
        try:
            import evo_lcm
        except ImportError:
            sys.exit("corridor.py: no `evo_lcm` module: `make` generates it "
                     "into build/gen/python from lcmtypes/evo_remote.lcm "
                     "(or set PYTHONPATH to where it is)")
    return lcm, evo_lcm


def own_data_url(url, name):
    """The episodes' URL `evo serve` would choose: the hello's, on port
    + 1 + (FNV-1a of the name) % 2000, so that simulators sharing a URL do
    not each receive the others' episodes. A URL without a port: itself."""
    if not url.startswith("udpm://"):
        return url
    colon = url.find(":", 7)
    digits = ""
    while colon >= 0 and colon + 1 + len(digits) < len(url) and \
            url[colon + 1 + len(digits)].isdigit():
        digits += url[colon + 1 + len(digits)]
    if colon < 0 or not digits or not 1 <= int(digits) <= 65535:
        return url
    h = 2166136261
    for b in name.encode():
        h = ((h ^ b) * 16777619) & 0xFFFFFFFF
    own = int(digits) + 1 + h % 2000
    if own > 65535:
        own -= 4000
    return "%s:%d%s" % (url[:colon], own, url[colon + 1 + len(digits):])


def name_ok(name):
    return (0 < len(name) < 64 and
            all(ch.isascii() and (ch.isalnum() or ch in "_-") for ch in name))


def main():
    p = argparse.ArgumentParser(
        description="A corridor with a goal, served to evo as a remote "
        "simulator over LCM (docs/remote.md).")
    p.add_argument("--name", default="corridor-%d" % os.getpid(),
                   help="the name evo finds it by (default corridor-PID)")
    p.add_argument("--environments", type=int, default=1, metavar="N",
                   help="episodes run at once, each in a world of its own "
                   "(1..%d, default 1)" % MAX_ENVIRONMENTS)
    p.add_argument("--url", default="udpm://239.255.76.67:7667?ttl=0",
                   help="the LCM URL (default LCM's own, this machine only)")
    p.add_argument("--data-url", metavar="URL",
                   help="the LCM URL of its episodes (default: the URL's "
                   "port + 1 + a hash of the name modulo 2000, as evo serve "
                   "does; 'same': the URL itself)")
    p.add_argument("--key-file", metavar="FILE",
                   help="the key shared with evo (the task's LCMKEYFILE): "
                   "every message sealed and checked (docs/remote.md, Keys)")
    p.add_argument("--log", metavar="FILE",
                   help="append a line per episode that ends: its seeds, "
                   "reward and ticks")
    a = p.parse_args()
    if not name_ok(a.name):
        p.error("--name '%s': a remote's name is 1..63 letters, digits, '_' "
                "or '-'" % a.name)
    if not 1 <= a.environments <= MAX_ENVIRONMENTS:
        p.error("--environments expects a whole number 1..%d, found %d" %
                (MAX_ENVIRONMENTS, a.environments))
    key = None
    if a.key_file:
        try:
            key = read_key(a.key_file)
        except (OSError, ValueError) as e:
            p.error("--key-file: %s" % e)
    lcm, types = import_types()

    stop = []
    signal.signal(signal.SIGTERM, lambda sig, frame: stop.append(sig))
    signal.signal(signal.SIGINT, lambda sig, frame: stop.append(sig))
    data_url = (a.url if a.data_url == "same" else
                a.data_url or own_data_url(a.url, a.name))
    try:
        lc = lcm.LCM(a.url)
        data = lcm.LCM(data_url) if data_url != a.url else lc
    except (IOError, RuntimeError) as e:
        sys.exit("corridor.py: cannot open LCM: %s" % e)
    log = open(a.log, "a") if a.log else None
    sim = Simulator(lc, data, data_url, types, a.name, a.environments, log,
                    key)
    sim.publish_hello()
    print("corridor: %s serves a corridor on %s (%d environment%s; its "
          "episodes on %s)" % (a.name, a.url, a.environments,
                               "" if a.environments == 1 else "s", data_url),
          flush=True)
    handle = {lc.fileno(): lc, data.fileno(): data}
    while not stop:
        # select, not lc.handle_timeout: Python runs the signal handlers
        # between two selects, so SIGTERM ends the loop at once
        ready, _, _ = select.select(list(handle), [], [], 0.1)
        for fd in ready:
            handle[fd].handle()
    sim.close()
    if log:
        log.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
