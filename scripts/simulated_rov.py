#!/usr/bin/env python3
"""A small simulated ROV for demos and tests: publishes geometry_msgs/PoseStamped on rov_pose (and, with
~publish_tf, the tf world_frame -> rov_frame) following a scripted dive: out from the spool, around, and
back, so the tether pays out and reels in. Waypoints are [t, x, y, z] in s and m (world frame, z up),
followed piecewise-linearly; the vehicle faces its direction of travel.

Parameters: ~rate [Hz] (20), ~world_frame (world), ~rov_frame (rov), ~publish_tf (false), ~loop (true),
~waypoints (list of [t, x, y, z]; default: the dive of scenarios/spool_payout.yaml).
"""
import math

import rospy
import tf2_ros
from geometry_msgs.msg import PoseStamped, TransformStamped

DIVE = [[0.0, 1.5, 0.0, -1.0], [16.0, 9.5, 0.0, -3.0], [26.0, 6.0, 7.0, -3.0], [42.0, 1.5, 0.5, -1.5],
        [50.0, 1.5, 0.5, -1.5]]


def position_at(waypoints, t):
    """Piecewise-linear position at t (held outside the waypoints' times)."""
    if t <= waypoints[0][0]:
        return waypoints[0][1:]
    for a, b in zip(waypoints, waypoints[1:]):
        if a[0] <= t <= b[0] and b[0] > a[0]:
            u = (t - a[0]) / (b[0] - a[0])
            return [a[i] + u * (b[i] - a[i]) for i in range(1, 4)]
    return waypoints[-1][1:]


def main():
    rospy.init_node("simulated_rov")
    rate_hz = float(rospy.get_param("~rate", 20.0))
    world = rospy.get_param("~world_frame", "world")
    rov = rospy.get_param("~rov_frame", "rov")
    publish_tf = bool(rospy.get_param("~publish_tf", False))
    loop = bool(rospy.get_param("~loop", True))
    waypoints = rospy.get_param("~waypoints", DIVE)
    if not waypoints or any(len(w) != 4 for w in waypoints):
        rospy.logfatal("simulated_rov: ~waypoints must be a non-empty list of [t, x, y, z]")
        return
    period = waypoints[-1][0]
    pub = rospy.Publisher("rov_pose", PoseStamped, queue_size=10)
    broadcaster = tf2_ros.TransformBroadcaster() if publish_tf else None
    rate = rospy.Rate(rate_hz)
    start = rospy.Time.now()
    yaw = 0.0
    previous = None
    while not rospy.is_shutdown():
        now = rospy.Time.now()
        if now < start:  # simulated time went backwards (bag loop): restart the dive
            start = now
        t = (now - start).to_sec()
        if loop and period > 0:
            t = math.fmod(t, period)
        x, y, z = position_at(waypoints, t)
        if previous is not None and math.hypot(x - previous[0], y - previous[1]) > 1e-4:
            yaw = math.atan2(y - previous[1], x - previous[0])
        previous = (x, y, z)
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
