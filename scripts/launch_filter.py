#!/usr/bin/env python3
"""Filters roslaunch's output for a person watching a demo (scripts/demo.sh pipes roslaunch through it):
what the nodes say stays, roslaunch's own chatter goes.

Removed: terminal escapes (colours, and the window-title sequence roslaunch writes before its first line);
the SUMMARY block (CLEAR PARAMETERS, PARAMETERS and NODES with their lists); start-up and shut-down lines
(log directory, master, process[...] started, killing, shutting down); and the end of the summary node
`quiet_node` (default tether_summary), which ends the demo by design. The end of any other node ("REQUIRED
process [...] has died!", "process has died [pid ..., exit code ...]", its log file) and every line of the
nodes (INFO, WARN, ERROR, the summary lines) stay.
Usage: roslaunch ... 2>&1 | launch_filter.py [quiet_node]
"""
import os
import re
import signal
import sys

# CSI sequences (colours: ESC [ ... m) and OSC sequences (the title: ESC ] 2 ; ... BEL or ESC \).
ESCAPES = re.compile(r"\x1b\[[0-9;?]*[A-Za-z]|\x1b\][^\x07\x1b]*(?:\x07|\x1b\\)?")
CHATTER = re.compile(
    r"^(\.\.\. logging to |Checking log |Done checking log |Press Ctrl-C|started roslaunch server|"
    r"auto-starting new master|process\[[^\]]*\]: started with pid|ROS_MASTER_URI=|setting /run_id|"
    r"started core service|\[[^\]]*\] killing on exit|shutting down processing monitor|"
    r"\.\.\. shutting down processing monitor|all processes on machine have died|done$)")


class LaunchFilter:
    """Keeps state across lines: the SUMMARY block spans many."""

    def __init__(self, quiet_node="tether_summary"):
        self.quiet_node = quiet_node
        self.in_summary = False
        self.seen_nodes = False
        self.in_quiet_end = False

    def keep(self, line):
        """The line cleaned of escapes, or None when it is roslaunch's chatter."""
        text = ESCAPES.sub("", line.rstrip("\r\n"))
        stripped = text.strip()
        if stripped == "SUMMARY":
            self.in_summary, self.seen_nodes = True, False
            return None
        if self.in_summary:
            # SUMMARY, ========, CLEAR PARAMETERS, PARAMETERS, NODES and their lists up to NODES' blank line.
            if stripped == "NODES":
                self.seen_nodes = True
            elif self.seen_nodes and stripped == "":
                self.in_summary = False
            return None
        if stripped == "" or CHATTER.match(stripped):
            return None
        # roslaunch frames the end of a required node between two rules of '=': "REQUIRED process [name-4]
        # has died!", how it ended, its log file, "Initiating shutdown!". Dropped for the quiet node, kept
        # (without the rules) for any other.
        if re.match(r"=+REQUIRED process \[", stripped):
            self.in_quiet_end = self.quiet_node is not None and ("[%s-" % self.quiet_node) in stripped
            return None if self.in_quiet_end else stripped.lstrip("=")
        if re.match(r"=+$", stripped):
            self.in_quiet_end = False
            return None
        if self.in_quiet_end:
            return None
        return text


def main():
    # Ctrl-C is roslaunch's to handle: the filter reads on until roslaunch has said its last and closed the pipe.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    launch_filter = LaunchFilter(sys.argv[1] if len(sys.argv) > 1 else "tether_summary")
    for line in iter(sys.stdin.readline, ""):  # each line as it comes, not a buffer at a time
        text = launch_filter.keep(line)
        if text is not None:
            print(text, flush=True)


if __name__ == "__main__":
    try:
        main()
    except BrokenPipeError:  # the reader left (demo.sh | head): stop quietly, as cat would
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        sys.exit(1)
