"""Renders latticedyn results (the .xdmf beside the .h5) to PNG or MP4 with ParaView, for docs and quick looks.

Run with ParaView's Python, under a virtual X display on a headless machine:

    xvfb-run -a pvpython scripts/render.py results/double_pendulum/double_pendulum.xdmf \
        --output docs/images/double_pendulum.png --times 0 0.5 1.0 --view xz
    xvfb-run -a pvpython scripts/render.py results/crane_slewing/slewing.xdmf \
        --movie slewing.mp4 --view iso --fps 20 --frames 200 --size 640 480

Several times are drawn over each other, later ones darker, to show a motion in one picture.
--movie renders one frame per output time (at most --frames of them, evenly spaced) with a fixed
camera that sees the model at all of them, and joins the frames with ffmpeg (H.264).
Lines are coloured by body, or by axial force with --color axial_force (strut ties, beams,
super truss members).
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile

from paraview.simple import (ColorBy, ExtractSurface, ForceTime, GetActiveViewOrCreate,
                             GetColorTransferFunction, GetScalarBar, Render, SaveScreenshot, Show, Tube,
                             XDMFReader)

# Where the camera stands, seen from the model's centre, and which way is up.
DIRECTIONS = {"xz": ((0, -1, 0), (0, 0, 1)), "yz": ((1, 0, 0), (0, 0, 1)),
              "xy": ((0, 0, 1), (0, 1, 0)), "iso": ((1, -1.4, 0.8), (0, 0, 1))}


def colour(display, view, a):
    if a.color == "axial_force":
        ColorBy(display, ("CELLS", "axial_force"))
        display.SetScalarBarVisibility(view, True)
        lut = GetColorTransferFunction("axial_force")
        lut.ApplyPreset("Cool to Warm", True)
        if a.range:
            lut.RescaleTransferFunction(-a.range, a.range)
            lut.AutomaticRescaleRangeMode = "Never"
        bar = GetScalarBar(lut, view)
        bar.Title = "axial force [N]"
        bar.ComponentTitle = ""
        bar.TitleColor = bar.LabelColor = [0, 0, 0]
    else:
        ColorBy(display, ("CELLS", "body"))
        GetColorTransferFunction("body").ApplyPreset("Set1", True)


def bounds_at(reader, times):
    """Union of the model's bounds at the given times."""
    lo, hi = [1e300] * 3, [-1e300] * 3
    for t in times:
        one = ForceTime(Input=reader, IgnorePipelineTime=1, ForcedTime=t)
        one.UpdatePipeline(t)
        b = one.GetDataInformation().GetBounds()
        for i in range(3):
            lo[i] = min(lo[i], b[2 * i])
            hi[i] = max(hi[i], b[2 * i + 1])
    return [v for i in range(3) for v in (lo[i], hi[i])]


def place_camera(view, bounds, direction):
    extent = max(bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4], 1e-3)
    camera = view.GetActiveCamera()
    cx, cy, cz = [(bounds[2 * i] + bounds[2 * i + 1]) / 2 for i in range(3)]
    (dx, dy, dz), up = DIRECTIONS[direction]
    norm = (dx * dx + dy * dy + dz * dz) ** 0.5
    camera.SetFocalPoint(cx, cy, cz)
    camera.SetPosition(cx + dx / norm * 10 * extent, cy + dy / norm * 10 * extent, cz + dz / norm * 10 * extent)
    camera.SetViewUp(*up)
    view.ResetCamera(bounds)


def make_view(size):
    view = GetActiveViewOrCreate("RenderView")
    view.ViewSize = size
    view.UseColorPaletteForBackground = 0
    view.Background = [1, 1, 1]
    view.OrientationAxesVisibility = 1
    return view


def picture(reader, steps, a):
    wanted = a.times if a.times else [steps[-1]]
    view = make_view(a.size)
    nearest = [min(steps, key=lambda s: abs(s - t)) for t in wanted]
    bounds = bounds_at(reader, nearest)
    extent = max(bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4], 1e-3)
    radius = a.radius if a.radius > 0 else 0.006 * extent
    for k, t in enumerate(nearest):
        one = ForceTime(Input=reader, IgnorePipelineTime=1, ForcedTime=t)
        # The XDMF reader gives an unstructured grid; tubes need poly data.
        tube = Tube(Input=ExtractSurface(Input=one), Radius=radius, NumberofSides=12)
        d = Show(tube, view)
        colour(d, view, a)
        # Earlier times lighter so a sequence reads as a motion.
        d.Opacity = 0.25 + 0.75 * (k + 1) / len(wanted)
    place_camera(view, bounds, a.view)
    Render(view)
    SaveScreenshot(a.output, view, ImageResolution=a.size)
    print(f"wrote {a.output} ({len(wanted)} time(s) of {len(steps)})")


def movie(reader, steps, a):
    if shutil.which("ffmpeg") is None:
        sys.exit("render.py: --movie needs ffmpeg (Debian package ffmpeg)")
    count = min(len(steps), max(1, a.frames))
    frames = [steps[round(i * (len(steps) - 1) / max(1, count - 1))] for i in range(count)]
    view = make_view(a.size)
    bounds = bounds_at(reader, [frames[0], frames[len(frames) // 2], frames[-1]])
    extent = max(bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4], 1e-3)
    radius = a.radius if a.radius > 0 else 0.006 * extent
    one = ForceTime(Input=reader, IgnorePipelineTime=1, ForcedTime=frames[0])
    tube = Tube(Input=ExtractSurface(Input=one), Radius=radius, NumberofSides=10)
    d = Show(tube, view)
    colour(d, view, a)
    place_camera(view, bounds, a.view)
    work = tempfile.mkdtemp(prefix="latticedyn_movie_")
    try:
        for i, t in enumerate(frames):
            one.ForcedTime = t
            Render(view)
            SaveScreenshot(os.path.join(work, f"frame_{i:05d}.png"), view, ImageResolution=a.size)
        # Even sizes for yuv420p; one frame per output time at --fps.
        cmd = ["ffmpeg", "-y", "-loglevel", "error", "-framerate", str(a.fps), "-i",
               os.path.join(work, "frame_%05d.png"), "-vf", "scale=trunc(iw/2)*2:trunc(ih/2)*2",
               "-c:v", "libx264", "-pix_fmt", "yuv420p", a.movie]
        subprocess.run(cmd, check=True)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print(f"wrote {a.movie} ({count} frames of {len(steps)} output times, t = {frames[0]:g} .. {frames[-1]:g} s)")


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("xdmf")
    p.add_argument("--output", help="PNG file to write")
    p.add_argument("--movie", help="MP4 file to write (all output times, see --frames, --fps)")
    p.add_argument("--times", type=float, nargs="*", default=None,
                   help="simulated times to draw in the PNG (default: the last one)")
    p.add_argument("--frames", type=int, default=300, help="at most this many movie frames")
    p.add_argument("--fps", type=int, default=20, help="movie frames per second")
    p.add_argument("--view", default="xz", choices=sorted(DIRECTIONS),
                   help="viewing direction (xz: x right, z up)")
    p.add_argument("--color", default="body", choices=["body", "axial_force"])
    # one positive number: pvpython takes a negative argument for one of its own options
    p.add_argument("--range", type=float, default=None, metavar="MAX",
                   help="colour range -MAX..MAX for --color axial_force (to compare two runs)")
    p.add_argument("--size", type=int, nargs=2, default=[1200, 800])
    p.add_argument("--radius", type=float, default=0.0,
                   help="tube radius in model units (0: a fraction of the model size)")
    a = p.parse_args()
    if not a.output and not a.movie:
        p.error("give --output (PNG) or --movie (MP4)")
    if not os.path.isfile(a.xdmf):
        sys.exit(f"render.py: no file {a.xdmf}")

    reader = XDMFReader(FileNames=[a.xdmf])
    reader.UpdatePipeline()
    steps = list(reader.TimestepValues) if reader.TimestepValues else [0.0]
    if a.output:
        picture(reader, steps, a)
    if a.movie:
        movie(reader, steps, a)


if __name__ == "__main__":
    main()
