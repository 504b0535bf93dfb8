#!/usr/bin/env python3
"""An example external vehicle simulator coupled to tether_node: a point vehicle (3-DOF translation) that
feels its tether, integrated at its own rate, publishing its pose on the topic the node reads.

The tether's pull comes from the node's ~coupling (rov_tether/TetherCoupling, once per physics step): the pull
F0 at the attachment point x0 moving at v0, and the tether's stiffness K = dF/dx and damping C = dF/dv there.
Each step the simulator applies F = F0 + K (x - x0) + C (v - v0) at its own state x, v, from the latest
message, with K and C inside its implicit step (coupled_step below): the stable way for a stiff tether. A taut
10 m tether at EA 1e5 N is a 1e4 N/m spring; on a 20 kg vehicle, applied explicitly, it needs steps below
2 sqrt(m / k) = 89 ms undamped and, delayed by a topic loop, below c / k = 1.4 ms with the vehicle's own drag
c: no simulator runs that fast, and the vehicle bounces off its tether (docs/node.md, "External vehicle
simulators"). ~tether_force: wrench applies the node's ~wrench as it comes, the old way, to show that.

A slack tether's message has no stiffness (F0, K, C zero): it cannot say where the tether comes taut again.
For ~slack_memory seconds of the node's time after the last taut message, the simulator keeps applying that
one (a unilateral spring: no pull until the vehicle is back where it pulled), so a tether that goes slack
for a moment and comes taut again acts at once, not a message delay late (interpolation_delay: 0.1 s at
0.5 m/s is 5 cm of stretch unseen, 500 N at 1e4 N/m). Beyond it, the tether is slack until a taut message
comes. The first time a tether comes taut is seen that late in any case: give the node interpolation_delay 0.

Until the first ~coupling message the vehicle is held at ~start (its tether's pull is not known yet); its pose
is published all along, so the node attaches it. Time: ROS time (/clock under use_sim_time); the vehicle steps
by 1 / ~rate until it reaches ROS time and publishes each step's pose, stamped with the step's time.

Parameters: ~rate [Hz] (100), ~mass [kg] (13.5), ~added_mass [kg] per world axis ([6.36, 7.12, 18.68]),
~linear_drag [N s/m] per axis ([13.7, 0, 33.0]), ~quadratic_drag [N s^2/m^2] per axis ([141, 217, 190]): the
BlueROV2 Heavy's surge, sway and heave of von Benzon et al. 2022 (docs/references.md), ~thrust [N] a
world-frame vector ([0, 0, 0]), ~start [m] ([0, 0, 0]), ~world_frame (world), ~pose_topic (rov_pose),
~coupling_topic (tether_node/coupling), ~slack_memory [s] (1.0), ~tether_force (coupling | wrench | none),
~wrench_topic (tether_node/wrench). A bad value (not a number, not finite, out of its range: ~rate in [0.5, 1000],
~mass > 0, the masses and drags >= 0, ~start within +-1e6 m, ~slack_memory in [0, 3600]) stops it with an error
naming the parameter, its value and its range (exit code 1). SIGTERM, SIGINT or a shutdown end it within 0.05 s
of waiting at any rate.

ROS time going back (a bag played in a loop, a simulator's reset) by more than a step restarts the vehicle's
clock there, with a warning; the tether's messages from before are forgotten (a ~coupling stamped more than
CLOCK_AHEAD past ROS time is from before the jump: dropped, and counted in a warning) and the vehicle waits for
the next one, held where it is. ROS time leaping ahead by more than
MAX_CATCH_UP is not stepped through (600 s at 1 kHz took 8 s of CPU, publishing poses long past): the vehicle
is held where it is and its clock jumps there, with a warning.
"""
import math
import signal
import time

import rospy
from geometry_msgs.msg import PoseStamped, WrenchStamped

from rov_tether.msg import TetherCoupling


def mat_vec(a, x):
    return [sum(a[i][k] * x[k] for k in range(3)) for i in range(3)]


def solve3(a, b):
    """x with a x = b for a 3x3 matrix a (Gaussian elimination with partial pivoting)."""
    m = [list(a[i]) + [b[i]] for i in range(3)]
    for c in range(3):
        p = max(range(c, 3), key=lambda r: abs(m[r][c]))
        m[c], m[p] = m[p], m[c]
        for r in range(c + 1, 3):
            f = m[r][c] / m[c][c]
            m[r] = [m[r][k] - f * m[c][k] for k in range(4)]
    x = [0.0, 0.0, 0.0]
    for r in (2, 1, 0):
        x[r] = (m[r][3] - sum(m[r][k] * x[k] for k in range(r + 1, 3))) / m[r][r]
    return x


def coupled_step(x, v, h, mass, drag, thrust, coupling):
    """One backward-Euler step of h [s] of a point vehicle on its tether: returns (x, v, pull) at its end.

    mass: 3x3 [kg] (rigid body and added mass); drag: 3x3 [N s/m], the drag linearised at v (linear +
    quadratic |v|); thrust [N], world frame; coupling: (F0, x0, v0, K, C) of the latest ~coupling, or None.
    Implicit in the tether, M (v' - v) = h (thrust - drag v' + F0 + K (x' - x0) + C (v' - v0)) with
    x' = x + h v':  (M + h drag - h C - h^2 K) v' = M v + h (thrust + F0 + K (x - x0) - C v0).
    K and C are negative semi-definite (moving away from the spool pulls harder towards it), so the matrix is
    positive definite at any stiffness and step: no rate is too slow for the tether. A cable cannot push: when
    the linearised pull would point against F0 (the vehicle closed on the spool since the message), the step
    is taken again with the tether slack."""
    if coupling is not None:
        f0, x0, v0, k, c = coupling
        a = [[mass[i][j] + h * drag[i][j] - h * c[i][j] - h * h * k[i][j] for j in range(3)] for i in range(3)]
        kx, cv, mv = mat_vec(k, [x[i] - x0[i] for i in range(3)]), mat_vec(c, v0), mat_vec(mass, v)
        v_new = solve3(a, [mv[i] + h * (thrust[i] + f0[i] + kx[i] - cv[i]) for i in range(3)])
        x_new = [x[i] + h * v_new[i] for i in range(3)]
        dx, dv = [x_new[i] - x0[i] for i in range(3)], [v_new[i] - v0[i] for i in range(3)]
        pull = [f0[i] + a_k + a_c for i, (a_k, a_c) in enumerate(zip(mat_vec(k, dx), mat_vec(c, dv)))]
        if sum(pull[i] * f0[i] for i in range(3)) > 0.0:
            return x_new, v_new, pull
    a = [[mass[i][j] + h * drag[i][j] for j in range(3)] for i in range(3)]  # slack: the vehicle alone
    mv = mat_vec(mass, v)
    v_new = solve3(a, [mv[i] + h * thrust[i] for i in range(3)])
    return [x[i] + h * v_new[i] for i in range(3)], v_new, [0.0, 0.0, 0.0]


def diagonal(values):
    return [[values[i] if i == j else 0.0 for j in range(3)] for i in range(3)]


# The private parameters' ranges: a bad value stops the simulator with an error naming it, its value and its range.
# ~rate: a pose at least every 2 s, the node's default stale_pose_timeout (sparser poses go stale between steps and
# the node stops waiting for them; a step as long as 1e6 s also slept through SIGTERM); at most 1 kHz, five times the
# node's default physics rate (200 Hz, 5 ms steps), which interpolates between poses anyway: more only loads Python
# (a step and its publish cost some 0.1 ms).
RATE_RANGE = (0.5, 1000.0)  # [Hz]
MAX_COORDINATE = 1e6  # [m] ~start: the node refuses poses beyond +-1e6 m (Tether::kMaxCoordinate)
MAX_SLACK_MEMORY = 3600.0  # [s] ~slack_memory: the node's longest stale_pose_timeout
SHUTDOWN_CHECK = 0.05  # [s] the longest a wait goes on without looking for shutdown
MAX_CATCH_UP = 1.0  # [s] ROS time further ahead than this is jumped to, not stepped through
CLOCK_AHEAD = 1.0  # [s] a ~coupling stamped further past ROS time than this is from before the clock went back


def number(value):
    """value as a float, or None when it is no number. A string that reads as one is one: `_rate:=1e3` on the
    command line is the string '1e3' (YAML 1.1 wants 1.0e3), which roslaunch's <param> gives as 1000.0."""
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        return None
    try:
        return float(value)
    except ValueError:
        return None


def bad_parameter(name, value, allowed):
    """The ValueError naming the parameter (resolved), the value it was given and what is allowed."""
    return ValueError("%s = %r: must be %s" % (rospy.resolve_name(name), value, allowed))


def scalar_param(name, default, ok, allowed):
    """The private parameter `name` as a finite float for which ok(x) holds; `allowed` says which."""
    value = rospy.get_param(name, default)
    x = number(value)
    if x is None or not math.isfinite(x) or not ok(x):
        raise bad_parameter(name, value, "a finite number " + allowed)
    return x


def vector_param(name, default, ok=lambda x: True, allowed=""):
    """The private parameter `name` as a list of 3 finite floats, each x with ok(x); `allowed` says which."""
    value = rospy.get_param(name, default)
    xs = [number(a) for a in value] if isinstance(value, (list, tuple)) and len(value) == 3 else None
    if xs is None or not all(x is not None and math.isfinite(x) and ok(x) for x in xs):
        raise bad_parameter(name, value, "a list of 3 finite numbers" + (", each " + allowed if allowed else ""))
    return xs


def text_param(name, default, choices=None):
    """The private parameter `name` as a non-empty string (one of `choices` when given)."""
    value = rospy.get_param(name, default)
    if not isinstance(value, str) or not value or (choices and value not in choices):
        raise bad_parameter(name, value, "one of " + ", ".join(choices) if choices else "a non-empty string")
    return value


class VehicleSim:
    """The vehicle, its latest tether message and its publisher."""

    def __init__(self):
        self.rate = scalar_param("~rate", 100.0, lambda x: RATE_RANGE[0] <= x <= RATE_RANGE[1],
                                 "in [%g, %g] Hz (a pose at least every 2 s, the node's default stale_pose_timeout; "
                                 "at most 5 x its default physics rate)" % RATE_RANGE)
        mass = scalar_param("~mass", 13.5, lambda x: x > 0.0, "> 0 kg")
        non_negative = lambda x: x >= 0.0  # noqa: E731
        added = vector_param("~added_mass", [6.36, 7.12, 18.68], non_negative, ">= 0 kg")
        self.linear = vector_param("~linear_drag", [13.7, 0.0, 33.0], non_negative, ">= 0 N s/m")
        self.quadratic = vector_param("~quadratic_drag", [141.0, 217.0, 190.0], non_negative, ">= 0 N s^2/m^2")
        self.thrust = vector_param("~thrust", [0.0, 0.0, 0.0])
        self.x = vector_param("~start", [0.0, 0.0, 0.0], lambda x: abs(x) <= MAX_COORDINATE,
                              "within +-%g m (the node refuses poses beyond)" % MAX_COORDINATE)
        self.frame = text_param("~world_frame", "world")
        self.tether_force = text_param("~tether_force", "coupling", ("coupling", "wrench", "none"))
        self.slack_memory = scalar_param("~slack_memory", 1.0, lambda x: 0.0 <= x <= MAX_SLACK_MEMORY,
                                         "in [0, %g] s" % MAX_SLACK_MEMORY)
        pose_topic = text_param("~pose_topic", "rov_pose")
        coupling_topic = text_param("~coupling_topic", "tether_node/coupling")
        wrench_topic = text_param("~wrench_topic", "tether_node/wrench")
        self.mass = diagonal([mass + a for a in added])
        self.v = [0.0, 0.0, 0.0]
        self.coupling = None  # (F0, x0, v0, K, C) the step applies: the latest ~coupling, or the last taut one
        self.last_taut = None  # (stamp [s], (F0, x0, v0, K, C)) of the last taut ~coupling
        self.wrench = None    # [N] the latest ~wrench's force (~tether_force: wrench)
        self.pull = [0.0, 0.0, 0.0]
        self.dropped = 0  # ~coupling messages from before the clock went back
        self.pub = rospy.Publisher(pose_topic, PoseStamped, queue_size=100)
        if self.tether_force == "coupling":
            rospy.Subscriber(coupling_topic, TetherCoupling, self.on_coupling, queue_size=1, tcp_nodelay=True)
        elif self.tether_force == "wrench":
            rospy.Subscriber(wrench_topic, WrenchStamped, self.on_wrench, queue_size=1, tcp_nodelay=True)

    def on_coupling(self, msg):
        f, p, u = msg.force, msg.position, msg.velocity
        k, c = msg.stiffness, msg.damping
        coupling = ([f.x, f.y, f.z], [p.x, p.y, p.z], [u.x, u.y, u.z],
                    [list(k[0:3]), list(k[3:6]), list(k[6:9])], [list(c[0:3]), list(c[3:6]), list(c[6:9])])
        stamp = msg.header.stamp.to_sec()
        if stamp > rospy.Time.now().to_sec() + CLOCK_AHEAD:
            self.dropped += 1  # from before the clock went back: its pull is for where the vehicle was then
            rospy.logwarn_throttle(5.0, "vehicle_sim: %d ~coupling messages stamped more than %.0f s past ROS time "
                                   "(from before the clock went back) dropped so far" % (self.dropped, CLOCK_AHEAD))
            return
        if msg.taut:
            self.last_taut = (stamp, coupling)
        elif self.last_taut is not None and stamp - self.last_taut[0] <= self.slack_memory:
            coupling = self.last_taut[1]  # slack for a moment: the last taut spring, unilateral
        self.coupling = coupling

    def restart(self, now, why):
        """The vehicle's clock restarts at ROS time `now` [s], held where it is; the tether's messages are
        forgotten (the next one comes from the node's time after the jump)."""
        rospy.logwarn("vehicle_sim: %s: the vehicle is held at [%.3f, %.3f, %.3f] m and steps on from %.3f s; "
                      "the tether's pull is taken again from its next message", why, self.x[0], self.x[1], self.x[2],
                      now)
        self.v = [0.0, 0.0, 0.0]
        self.coupling = self.last_taut = self.wrench = None

    def on_wrench(self, msg):
        f = msg.wrench.force
        self.wrench = [f.x, f.y, f.z]

    def started(self):
        """The vehicle moves once the tether's pull is known (or is not wanted)."""
        return self.tether_force == "none" or (self.coupling if self.tether_force == "coupling" else self.wrench)

    def step(self, h):
        if not self.started():
            return
        drag = diagonal([self.linear[i] + self.quadratic[i] * abs(self.v[i]) for i in range(3)])
        if self.tether_force == "wrench":
            # The old way: the last published pull as a given force, explicit and late.
            thrust = [self.thrust[i] + self.wrench[i] for i in range(3)]
            self.x, self.v, _ = coupled_step(self.x, self.v, h, self.mass, drag, thrust, None)
            self.pull = list(self.wrench)
        else:
            self.x, self.v, self.pull = coupled_step(self.x, self.v, h, self.mass, drag, self.thrust, self.coupling)

    def publish(self, t):
        msg = PoseStamped()
        msg.header.stamp = rospy.Time.from_sec(t)
        msg.header.frame_id = self.frame
        msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = self.x
        msg.pose.orientation.w = 1.0
        self.pub.publish(msg)


_stop_signals = []  # SIGTERM or SIGINT received: the handler only appends here


def _on_signal(signum, _frame):
    # rospy's own handler runs its shutdown hooks here, on the main thread, between two of its bytecodes: one that
    # lands inside publish(), which holds the topic's lock, closes the topic and waits for that lock for good (a
    # suspected hang of the 1 kHz simulator on SIGTERM). This one takes no lock; the loop shuts rospy down.
    _stop_signals.append(signum)


def stopping():
    """A signal asked to stop, or rospy shut down (rosnode kill, the master's shutdown)."""
    return bool(_stop_signals) or rospy.is_shutdown()


def sleep_until(due, back):
    """Until ROS time reaches due [s], goes back below `back` [s] (the loop then restarts the vehicle's clock), or
    shutdown (SIGTERM, SIGINT, rosnode kill: the handlers only set a flag, and a sleep as long as a step at a low
    ~rate went on after it). Wall clock: in slices of at most SHUTDOWN_CHECK. Under /clock this waits on the
    condition rospy.sleep waits on, against due itself: rospy.sleep(due - now) counts from the time it reads
    itself, later than now when a /clock message came between, and then sleeps past due, for good when the clock
    waits for this simulator (a lockstep driver such as external_coupling.test)."""
    if rospy.rostime.is_wallclock():
        while not stopping():
            now = rospy.Time.now().to_sec()
            if now >= due or now < back:
                return
            time.sleep(min(due - now, SHUTDOWN_CHECK))
        return
    cond = rospy.rostime.get_rostime_cond()
    with cond:
        while not stopping() and back <= rospy.Time.now().to_sec() < due - 1e-9:
            cond.wait(SHUTDOWN_CHECK)


def wait_for_clock():
    """Until simulated time has started (the first /clock), or shutdown. (rospy.sleep raises on shutdown.)"""
    cond = rospy.rostime.get_rostime_cond()
    with cond:
        while not stopping() and rospy.Time.now().is_zero():
            cond.wait(SHUTDOWN_CHECK)


def main():
    rospy.init_node("vehicle_sim", disable_signals=True)
    signal.signal(signal.SIGTERM, _on_signal)
    signal.signal(signal.SIGINT, _on_signal)
    try:
        sim = VehicleSim()
    except ValueError as error:
        rospy.logfatal("vehicle_sim: %s", error)
        raise SystemExit(1)
    h = 1.0 / sim.rate
    wait_for_clock()
    if stopping():
        rospy.signal_shutdown("stopped")
        return
    t = rospy.Time.now().to_sec()
    sim.publish(t)
    rospy.loginfo("vehicle_sim: %.0f Hz, thrust [%.1f, %.1f, %.1f] N, tether force from %s", sim.rate,
                  sim.thrust[0], sim.thrust[1], sim.thrust[2], sim.tether_force)
    while not stopping():
        now = rospy.Time.now().to_sec()
        jump = None
        if now < t - h:
            jump = "ROS time went back from %.3f s to %.3f s" % (t, now)
        elif now - t > MAX_CATCH_UP:
            jump = "ROS time leapt %.3f s ahead (more than %.1f s: not stepped through)" % (now - t, MAX_CATCH_UP)
        if jump:
            sim.restart(now, jump)
            t = now
            sim.publish(t)
        while t + h <= now + 1e-9 and not stopping():  # catch up with ROS time in steps of exactly h
            sim.step(h)
            t += h
            sim.publish(t)
        sleep_until(t + h, t - h)
    rospy.signal_shutdown("signal %d" % _stop_signals[0] if _stop_signals else "shutdown")


if __name__ == "__main__":
    main()
