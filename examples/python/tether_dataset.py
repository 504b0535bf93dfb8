#!/usr/bin/env python3
"""Writes a segmentation dataset of a tether (the paper's second use, docs/python.md): the demo's dive
(scenarios/spool_payout.yaml: out 8 m, diving, around and back on a brake winch) seen by a fixed camera 12 m to
its side, one frame a second: the tether's mask (PNG, 255 where it is seen), its depth (float32 metres along the
optical axis, NaN elsewhere, in one .npz) and an index.

    python3 examples/python/tether_dataset.py [--out DIR] [--seconds 50]    # DIR/mask_NNNN.png, depth.npz, index.csv
"""
import argparse
import csv
import math
import pathlib

import numpy as np
from PIL import Image

import rov_tether

ROOT = pathlib.Path(__file__).resolve().parents[2]
# 640 x 480, 77 degrees across; the camera at (5, -12, -2) looking along +y, level: its optical frame (z forward,
# x right, y down) is the world's turned -90 degrees about x, the quaternion [x, y, z, w] below.
CAMERA = dict(width=640, height=480, K=[400.0, 0.0, 319.5, 0.0, 400.0, 239.5, 0.0, 0.0, 1.0])
POSITION = [5.0, -12.0, -2.0]
ORIENTATION = [-math.sqrt(0.5), 0.0, 0.0, math.sqrt(0.5)]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default="tether_dataset", help="output directory")
    parser.add_argument("--seconds", type=float, default=50.0, help="how much of the dive [s]")
    arguments = parser.parse_args()
    out = pathlib.Path(arguments.out)
    out.mkdir(parents=True, exist_ok=True)

    world = rov_tether.World.from_scenario(str(ROOT / "scenarios" / "spool_payout.yaml"))
    camera = rov_tether.Camera(**CAMERA)
    depths = {}
    with open(out / "index.csv", "w", newline="") as index:
        writer = csv.writer(index)
        writer.writerow(["frame", "t", "mask", "pixels", "nearest_m", "deployed_length_m"])
        for frame in range(int(arguments.seconds) + 1):
            world.advance_to(float(frame))
            mask, depth = camera.render(world, POSITION, ORIENTATION)
            name = "mask_%04d.png" % frame
            Image.fromarray(mask).save(out / name)  # 8-bit greyscale PNG
            depths["depth_%04d" % frame] = depth
            seen = int(np.count_nonzero(mask))
            nearest = float(np.nanmin(depth)) if seen else math.nan
            writer.writerow([frame, world.time, name, seen, "%.3f" % nearest,
                             "%.3f" % world.tethers[0].deployed_length])
    np.savez_compressed(out / "depth.npz", **depths)
    print("wrote %d frames to %s (masks, depth.npz, index.csv)" % (len(depths), out))


if __name__ == "__main__":
    main()
