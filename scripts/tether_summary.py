#!/usr/bin/env python3
"""Prints a live one-line summary of tether_node: deployed length, tension at the vehicle, winch, and the
physics real-time factor from /diagnostics. ~state_topic (/tether_node/state), ~period [s] (1.0),
~duration [s] (0 = until shut down), ~label ("": a word put before each line, to tell several summaries apart)."""
import math

import rospy
from diagnostic_msgs.msg import DiagnosticArray

latest = {"state": None, "rtf": float("nan"), "diag": ""}


def diagnostics_name(state_topic):
    """The names the /diagnostics status of the tether publishing `state_topic` may have: the node's updater
    calls it "<node>: tether" for <node>/state and "<node>: tether <name>" for <node>/<name>/state (several
    tethers), <node> being the node's full name without its leading slash (its namespace included). Both
    readings of the topic are kept (only one exists), so each summary reads its own tether's status, not the
    last one whose name ends in "tether"; None for a topic not ending in /state (any tether's status)."""
    parts = [part for part in state_topic.split("/") if part]
    if len(parts) < 2 or parts[-1] != "state":
        return None
    names = {"%s: tether" % "/".join(parts[:-1])}
    if len(parts) >= 3:
        names.add("%s: tether %s" % ("/".join(parts[:-2]), parts[-2]))
    return names


def on_state(msg):
    latest["state"] = msg


def on_diagnostics(msg, name=None):
    """Keeps the message and real-time factor of the status named in `name` (a set; None: any tether's)."""
    for status in msg.status:
        if status.name in name if name else status.name.endswith("tether"):
            latest["diag"] = status.message
            for kv in status.values:
                if kv.key == "physics real-time factor":
                    latest["rtf"] = float(kv.value)


def summary_line(elapsed, state, rtf, diag):
    """One line of the summary: `elapsed` [s] since the first state, a TetherState (or anything with its
    fields), the physics real-time factor (NaN until /diagnostics has reported one, and 0 while the physics
    has simulated nothing, before the first vehicle pose: neither is a measured factor) and the diagnostics'
    message."""
    physics = ("physics %6.0fx real time" % rtf if math.isfinite(rtf) and rtf > 0.0
               else "physics  not yet measured")  # as wide as the measured form, so the columns stay put
    return ("t %6.1f s | deployed %6.2f m of %.0f | tension vehicle %7.2f N, max %7.2f N | winch %-7s %+5.2f m/s"
            " | %s | %s" % (elapsed, state.deployed_length, state.cable_length, state.tension_vehicle,
                            state.max_tension, state.winch_mode, state.winch_speed, physics,
                            diag or "no diagnostics yet"))


def main():
    # Imported here, so summary_line can be checked without a build (test/check_demo_output.py).
    from rov_tether.msg import TetherState

    rospy.init_node("tether_summary", anonymous=True)
    topic = rospy.get_param("~state_topic", "/tether_node/state")
    period = float(rospy.get_param("~period", 1.0))
    duration = float(rospy.get_param("~duration", 0.0))
    label = str(rospy.get_param("~label", ""))
    rospy.Subscriber(topic, TetherState, on_state)
    rospy.Subscriber("/diagnostics", DiagnosticArray, on_diagnostics, callback_args=diagnostics_name(topic))
    # ~duration counts from the first clock (under /clock, time is 0 until it comes), waiting included.
    while not rospy.is_shutdown() and rospy.Time.now().is_zero():
        rospy.sleep(0.01)
    start = rospy.Time.now()
    first_stamp = None
    while not rospy.is_shutdown():
        rospy.sleep(period)
        s = latest["state"]
        if s is None:
            print("waiting for %s ..." % topic, flush=True)
        else:
            if first_stamp is None or s.header.stamp < first_stamp:
                first_stamp = s.header.stamp
            line = summary_line((s.header.stamp - first_stamp).to_sec(), s, latest["rtf"], latest["diag"])
            print(("%-9s " % label if label else "") + line, flush=True)
        if duration > 0 and (rospy.Time.now() - start).to_sec() >= duration:
            break


if __name__ == "__main__":
    try:
        main()
    except rospy.ROSInterruptException:
        pass
