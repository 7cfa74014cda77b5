"""Render a run's .rrd headless to a PNG (what a reader sees when replaying it in Rerun).

    python -m pidamper.runlog.screenshot out/resonance.rrd docs/rerun-resonance.png [--time 30]

Needs a Vulkan driver; without a GPU, Mesa's software one (Debian: mesa-vulkan-drivers,
libvulkan1).  The viewer runs headless and never opens a window.
"""
import argparse
import os
import sys
import time
from pathlib import Path

import rerun.experimental as rre


def screenshot(rrd, png, at=None, port=9877, size=None):
    os.environ.setdefault("WGPU_BACKEND", "vulkan")
    beside = Path(sys.executable).with_name("rerun")  # the viewer of this environment's rerun-sdk
    viewer = rre.ViewerClient.spawn(headless=True, port=port, hide_welcome_screen=True,
                                    executable_path=str(beside) if beside.exists() else None)
    try:
        viewer.open(str(Path(rrd).resolve()))
        if at is not None:
            viewer.set_time("sim_time", duration=float(at), play_state="paused")
        time.sleep(2.0)  # let the views lay out and load their data
        png_bytes = viewer.take_screenshot(max_size=size)
    finally:
        viewer.quit()
    Path(png).write_bytes(png_bytes)
    return Path(png)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("rrd")
    parser.add_argument("png")
    parser.add_argument("--time", type=float, help="simulation time [s] to show (default: the end)")
    parser.add_argument("--max-size", type=int, default=None)
    args = parser.parse_args(argv)
    print(screenshot(args.rrd, args.png, args.time, size=args.max_size))


if __name__ == "__main__":
    main()
