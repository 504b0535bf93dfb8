#!/usr/bin/env python3
"""A small simulated ROV for demos and tests: publishes geometry_msgs/PoseStamped on rov_pose (and, with
~publish_tf, the tf world_frame -> rov_frame) following a scripted dive: out from the spool, around, and
back, so the tether pays out and reels in. Waypoints are [t, x, y, z] in s and m (world frame, z up),
followed piecewise-linearly. The vehicle turns towards its direction of travel at no more than
~max_yaw_rate, so at a waypoint it keeps moving while it turns instead of turning in one pose: a tether
attached behind the vehicle then never moves faster than the vehicle's speed plus what the turn adds
(|attachment offset| x yaw rate).

The dive's clock starts when someone listens: until rov_pose has a subscriber (the tether node), for at
most ~wait_for_listener seconds, the vehicle holds its first waypoint and publishes it. A tether node that
starts slowly (a sanitizer build, a loaded machine) then attaches to the vehicle at the start of its dive,
not to a vehicle already under way, whose first pose would lay the cable out taut and jerk it.

With ~loop the dive repeats; when the last waypoint is not the first, a closing leg takes the vehicle back
to the start at the dive's slowest speed, so the loop has no jump either.

With ~camera_frame, the vehicle carries a camera: a static tf rov_frame -> camera_frame, the camera's
optical frame (z forward, x right, y down) at ~camera_pose = [x, y, z, roll, pitch, yaw] (m and deg) in
the vehicle frame, the angles those of a frame looking along its x axis with z up (pitch > 0 looks down),
as a scenario's `cameras:` entries give them. (Debian ships no static_transform_publisher.)

Parameters: ~rate [Hz] (20, in [0.5, 1000]), ~world_frame (world), ~rov_frame (rov), ~publish_tf (false), ~loop
(true), ~max_yaw_rate [deg/s] (30), ~wait_for_listener [s] (30; 0 starts at once), ~waypoints (list of [t, x, y, z],
finite numbers, the times increasing; default: the dive of scenarios/spool_payout.yaml), ~camera_frame ("" = none),
~camera_pose ([0, 0, 0, 0, 0, 0]). A bad value stops it with an error naming the parameter (exit code 1).

Under simulated time nothing is published before the first /clock (ROS time 0), and the dive's clock starts at the
first time it reads after that, also with ~wait_for_listener 0; a pose is never published twice with one stamp.
"""
import math
import sys
import time

import rospy
import tf2_ros
from geometry_msgs.msg import PoseStamped, TransformStamped

DIVE = [[0.0, 1.5, 0.0, -1.0], [16.0, 9.5, 0.0, -3.0], [26.0, 6.0, 7.0, -3.0], [42.0, 1.5, 0.5, -1.5],
        [50.0, 1.5, 0.5, -1.5]]

# [deg/s] Heading rate limit. Work-class ROVs turn at some 30-60 deg/s; the slow end keeps the demo's turns
# (up to 119 degrees at a waypoint) about 4 s long, so the attachment 0.3 m behind the vehicle moves at
# most 0.3 m x 0.52 rad/s = 0.16 m/s faster than the vehicle.
MAX_YAW_RATE = 30.0


def position_at(waypoints, t):
    """Piecewise-linear position at t (held outside the waypoints' times)."""
    if t <= waypoints[0][0]:
        return waypoints[0][1:]
    for a, b in zip(waypoints, waypoints[1:]):
        if a[0] <= t <= b[0] and b[0] > a[0]:
            u = (t - a[0]) / (b[0] - a[0])
            return [a[i] + u * (b[i] - a[i]) for i in range(1, 4)]
    return waypoints[-1][1:]


def leg_velocity(a, b):
    """[m/s] velocity along the leg from waypoint a to waypoint b (zero for a jump or a hold)."""
    dt = b[0] - a[0]
    return [(b[i] - a[i]) / dt if dt > 0 else 0.0 for i in range(1, 4)]


def travel_heading(waypoints, t):
    """[rad] direction of horizontal travel at t, or None while the vehicle does not move horizontally."""
    for a, b in zip(waypoints, waypoints[1:]):
        if a[0] <= t < b[0]:
            vx, vy, _ = leg_velocity(a, b)
            return math.atan2(vy, vx) if math.hypot(vx, vy) > 1e-6 else None
    return None


def max_speed(waypoints):
    """[m/s] the fastest leg's speed: no pose-to-pose move of the vehicle exceeds it."""
    return max([math.sqrt(sum(v * v for v in leg_velocity(a, b))) for a, b in zip(waypoints, waypoints[1:])]
               or [0.0])


def closed_loop(waypoints):
    """The waypoints plus, when the dive does not end where it starts, a closing leg back to the start at the
    slowest moving leg's speed."""
    gap = math.dist(waypoints[-1][1:], waypoints[0][1:])
    if gap < 1e-9:
        return list(waypoints)
    speeds = [math.sqrt(sum(v * v for v in leg_velocity(a, b))) for a, b in zip(waypoints, waypoints[1:])]
    speeds = [s for s in speeds if s > 0]
    speed = min(speeds) if speeds else 0.5  # [m/s] a dive that never moves: a slow return
    return list(waypoints) + [[waypoints[-1][0] + gap / speed] + list(waypoints[0][1:])]


def optical_quaternion(roll, pitch, yaw):
    """[x, y, z, w] of the optical frame (z forward, x right, y down) of a camera whose body frame (x along
    the view, z up) has roll, pitch, yaw [deg]: R = Rz(yaw) Ry(pitch) Rx(roll) times the body-to-optical
    rotation (optical z = body x, x = -body y, y = -body z)."""
    r, p, y = (math.radians(a) for a in (roll, pitch, yaw))
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    body = [[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr]]
    optical = [[0, 0, 1], [-1, 0, 0], [0, -1, 0]]
    m = [[sum(body[i][k] * optical[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    # Rotation matrix to quaternion (Shepperd's method, the largest of w, x, y, z first).
    trace = m[0][0] + m[1][1] + m[2][2]
    if trace > 0:
        s = 2 * math.sqrt(1 + trace)
        return [(m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s, s / 4]
    i = max(range(3), key=lambda k: m[k][k])
    j, k = (i + 1) % 3, (i + 2) % 3
    s = 2 * math.sqrt(1 + m[i][i] - m[j][j] - m[k][k])
    q = [0.0, 0.0, 0.0, (m[k][j] - m[j][k]) / s]
    q[i] = s / 4
    q[j] = (m[j][i] + m[i][j]) / s
    q[k] = (m[k][i] + m[i][k]) / s
    return q


def wrap(angle):
    """angle in (-pi, pi]"""
    return math.atan2(math.sin(angle), math.cos(angle))


class Dive:
    """The scripted dive: position along the waypoints, and a heading that turns towards the direction of
    travel at most max_yaw_rate [deg/s]. pose(t) takes the time since the start [s], non-decreasing between
    calls (restart() begins again)."""

    def __init__(self, waypoints, loop=True, max_yaw_rate=MAX_YAW_RATE):
        self.waypoints = closed_loop(waypoints) if loop else list(waypoints)
        self.loop = loop
        self.period = self.waypoints[-1][0]
        self.max_yaw_rate = math.radians(max_yaw_rate)  # [rad/s]
        self.restart()

    def restart(self):
        # Start facing the first horizontal leg, so the dive does not begin with a turn.
        headings = [travel_heading(self.waypoints, a[0]) for a in self.waypoints]
        self.yaw = next((h for h in headings if h is not None), 0.0)
        self.last_t = None

    def pose(self, t):
        """Position [x, y, z] [m] and yaw [rad] at t [s] since the start."""
        if self.loop and self.period > 0:
            t_dive = math.fmod(t, self.period)
        else:
            t_dive = t
        heading = travel_heading(self.waypoints, t_dive)
        if heading is not None and self.last_t is not None:
            limit = self.max_yaw_rate * max(t - self.last_t, 0.0)
            self.yaw = wrap(self.yaw + max(-limit, min(limit, wrap(heading - self.yaw))))
        self.last_t = t
        return position_at(self.waypoints, t_dive), self.yaw


RATE_RANGE = (0.5, 1000.0)  # [Hz] as scripts/vehicle_sim.py's


def rate_problem(value):
    """"" when ~rate `value` is a finite number of Hz in RATE_RANGE, else why not."""
    try:
        rate = float(value)
    except (TypeError, ValueError):
        rate = float("nan")
    if isinstance(value, bool) or not RATE_RANGE[0] <= rate <= RATE_RANGE[1]:
        return "~rate = %r: must be a finite number in [%g, %g] Hz" % (value, RATE_RANGE[0], RATE_RANGE[1])
    return ""


def waypoints_problem(waypoints):
    """"" when `waypoints` is a non-empty list of [t, x, y, z] of finite numbers with increasing times, else why
    not: a time that does not increase would be a jump of the vehicle in no time (a 7 m jump in one pose)."""
    if not isinstance(waypoints, (list, tuple)) or not waypoints:
        return "~waypoints = %r: must be a non-empty list of [t, x, y, z]" % (waypoints,)
    for i, w in enumerate(waypoints):
        ok = isinstance(w, (list, tuple)) and len(w) == 4 and all(
            isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in w)
        if not ok:
            return "~waypoints[%d] = %r: must be [t, x, y, z], four finite numbers (s, m)" % (i, w)
        if i > 0 and not w[0] > waypoints[i - 1][0]:
            return ("~waypoints[%d]: its time %g s must be after the one before, %g s (a vehicle cannot jump)"
                    % (i, w[0], waypoints[i - 1][0]))
    return ""


def sleep(rate):
    """Until the rate's next tick; a clock that went back (bag loop) ends it early, and the loop restarts the dive."""
    try:
        rate.sleep()
    except rospy.ROSTimeMovedBackwardsException:
        pass


def main():
    rospy.init_node("simulated_rov")
    rate_value = rospy.get_param("~rate", 20.0)
    problem = rate_problem(rate_value)
    if problem:
        rospy.logfatal("simulated_rov: %s", problem)
        sys.exit(1)
    rate_hz = float(rate_value)
    world = rospy.get_param("~world_frame", "world")
    rov = rospy.get_param("~rov_frame", "rov")
    publish_tf = bool(rospy.get_param("~publish_tf", False))
    loop = bool(rospy.get_param("~loop", True))
    max_yaw_rate = float(rospy.get_param("~max_yaw_rate", MAX_YAW_RATE))
    waypoints = rospy.get_param("~waypoints", DIVE)
    problem = waypoints_problem(waypoints)
    if problem:
        rospy.logfatal("simulated_rov: %s", problem)
        sys.exit(1)
    if not max_yaw_rate > 0 or math.isinf(max_yaw_rate):
        rospy.logfatal("simulated_rov: ~max_yaw_rate must be finite and positive [deg/s], got %s", max_yaw_rate)
        sys.exit(1)
    wait_for_listener = float(rospy.get_param("~wait_for_listener", 30.0))
    if not wait_for_listener >= 0 or math.isinf(wait_for_listener):
        rospy.logfatal("simulated_rov: ~wait_for_listener must be finite and >= 0 [s], got %s", wait_for_listener)
        sys.exit(1)
    camera_frame = rospy.get_param("~camera_frame", "")
    camera_pose = rospy.get_param("~camera_pose", [0.0] * 6)
    if camera_frame and (len(camera_pose) != 6 or not all(math.isfinite(float(v)) for v in camera_pose)):
        rospy.logfatal("simulated_rov: ~camera_pose must be [x, y, z, roll, pitch, yaw] (m, deg), got %s",
                       camera_pose)
        sys.exit(1)
    static_broadcaster = None
    if camera_frame:
        static_broadcaster = tf2_ros.StaticTransformBroadcaster()
        mount = TransformStamped()
        mount.header.stamp = rospy.Time.now()
        mount.header.frame_id = rov
        mount.child_frame_id = camera_frame
        mount.transform.translation.x, mount.transform.translation.y, mount.transform.translation.z = \
            (float(v) for v in camera_pose[:3])
        q = optical_quaternion(*(float(v) for v in camera_pose[3:]))
        r = mount.transform.rotation
        r.x, r.y, r.z, r.w = q
        static_broadcaster.sendTransform(mount)
    dive = Dive(waypoints, loop, max_yaw_rate)
    pub = rospy.Publisher("rov_pose", PoseStamped, queue_size=10)
    broadcaster = tf2_ros.TransformBroadcaster() if publish_tf else None
    rate = rospy.Rate(rate_hz)
    # Under simulated time, ROS time is 0 until the first /clock: the dive's clock starts after it (a bag's epoch
    # read as time since 0 put the first pose far along the path).
    while rospy.Time.now().is_zero() and not rospy.is_shutdown():
        rospy.rostime.wallsleep(0.01)
    start = rospy.Time.now()
    last_stamp = None
    # The wait is timed on the wall clock: under simulated time, ROS time is 0 until /clock ticks and can
    # jump (a bag's epoch, a loop back), neither of which says how long the vehicle has waited.
    waiting_since = time.monotonic()
    waiting = wait_for_listener > 0
    while not rospy.is_shutdown():
        now = rospy.Time.now()
        if waiting:
            if pub.get_num_connections() > 0:
                waiting = False
            elif time.monotonic() - waiting_since >= wait_for_listener:
                waiting = False
                rospy.logwarn("simulated_rov: nobody subscribed to %s within ~wait_for_listener = %.0f s: "
                              "the dive starts anyway", pub.resolved_name, wait_for_listener)
            start = now  # the dive's clock starts when the waiting ends: until then, its first pose
        if now < start:  # simulated time went backwards (bag loop): restart the dive
            start = now
            dive.restart()
        if now == last_stamp:  # the clock has not moved since the last pose: one pose a stamp
            sleep(rate)
            continue
        last_stamp = now
        (x, y, z), yaw = dive.pose((now - start).to_sec())
        msg = PoseStamped()
        msg.header.stamp = now
        msg.header.frame_id = world
        msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = x, y, z
        msg.pose.orientation.z = math.sin(yaw / 2)
        msg.pose.orientation.w = math.cos(yaw / 2)
        pub.publish(msg)
        if broadcaster is not None:
            tf = TransformStamped()
            tf.header = msg.header
            tf.child_frame_id = rov
            tf.transform.translation.x, tf.transform.translation.y, tf.transform.translation.z = x, y, z
            tf.transform.rotation = msg.pose.orientation
            broadcaster.sendTransform(tf)
        sleep(rate)


if __name__ == "__main__":
    try:
        main()
    except rospy.ROSInterruptException:
        pass
