#!/usr/bin/env python3
"""A small simulated ROV for demos and tests: publishes geometry_msgs/PoseStamped on rov_pose (and, with
~publish_tf, the tf world_frame -> rov_frame) following a scripted dive: out from the spool, around, and
back, so the tether pays out and reels in. Waypoints are [t, x, y, z] in s and m (world frame, z up),
followed piecewise-linearly. The vehicle turns towards its direction of travel at no more than
~max_yaw_rate, so at a waypoint it keeps moving while it turns instead of turning in one pose: a tether
attached behind the vehicle then never moves faster than the vehicle's speed plus what the turn adds
(|attachment offset| x yaw rate).

With ~loop the dive repeats; when the last waypoint is not the first, a closing leg takes the vehicle back
to the start at the dive's slowest speed, so the loop has no jump either.

Parameters: ~rate [Hz] (20), ~world_frame (world), ~rov_frame (rov), ~publish_tf (false), ~loop (true),
~max_yaw_rate [deg/s] (30), ~waypoints (list of [t, x, y, z]; default: the dive of
scenarios/spool_payout.yaml).
"""
import math

import rospy
import tf2_ros
from geometry_msgs.msg import PoseStamped, TransformStamped

DIVE = [[0.0, 1.5, 0.0, -1.0], [16.0, 9.5, 0.0, -3.0], [26.0, 6.0, 7.0, -3.0], [42.0, 1.5, 0.5, -1.5],
        [50.0, 1.5, 0.5, -1.5]]

# [deg/s] Heading rate limit. Work-class ROVs turn at some 30-60 deg/s; the slow end keeps the demo's turns
# (up to 117 degrees at a waypoint) about 4 s long, so the attachment 0.3 m behind the vehicle moves at
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


def main():
    rospy.init_node("simulated_rov")
    rate_hz = float(rospy.get_param("~rate", 20.0))
    world = rospy.get_param("~world_frame", "world")
    rov = rospy.get_param("~rov_frame", "rov")
    publish_tf = bool(rospy.get_param("~publish_tf", False))
    loop = bool(rospy.get_param("~loop", True))
    max_yaw_rate = float(rospy.get_param("~max_yaw_rate", MAX_YAW_RATE))
    waypoints = rospy.get_param("~waypoints", DIVE)
    if not waypoints or any(len(w) != 4 for w in waypoints):
        rospy.logfatal("simulated_rov: ~waypoints must be a non-empty list of [t, x, y, z]")
        return
    if not max_yaw_rate > 0:
        rospy.logfatal("simulated_rov: ~max_yaw_rate must be positive [deg/s], got %s", max_yaw_rate)
        return
    dive = Dive(waypoints, loop, max_yaw_rate)
    pub = rospy.Publisher("rov_pose", PoseStamped, queue_size=10)
    broadcaster = tf2_ros.TransformBroadcaster() if publish_tf else None
    rate = rospy.Rate(rate_hz)
    start = rospy.Time.now()
    while not rospy.is_shutdown():
        now = rospy.Time.now()
        if now < start:  # simulated time went backwards (bag loop): restart the dive
            start = now
            dive.restart()
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
        try:
            rate.sleep()
        except rospy.ROSTimeMovedBackwardsException:
            pass


if __name__ == "__main__":
    try:
        main()
    except rospy.ROSInterruptException:
        pass
