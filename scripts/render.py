"""Renders latticedyn results (the .xdmf beside the .h5) to PNG or MP4 with ParaView, for docs and quick looks.

Run with ParaView's Python, under a virtual X display on a headless machine:

    xvfb-run -a pvpython scripts/render.py results/double_pendulum/double_pendulum.xdmf \
        --output docs/images/double_pendulum.png --times 0 0.5 1.0 --view xz
    xvfb-run -a pvpython scripts/render.py results/crane_slewing/slewing.xdmf \
        --movie slewing.mp4 --view iso --fps 20 --frames 200 --size 640 480

Several times are drawn over each other, later ones darker, to show a motion in one picture.
--movie renders one frame per output time (at most --frames of them, evenly spaced) with a fixed
camera that sees the model at all of them, and joins the frames with ffmpeg (H.264).

What is drawn: the "members" block of each output time (the line cells: elements and rigid
bodies' draw lines) as tubes and the "joints" block (one vertex per model joint) as spheres,
so every body shows, also a rigid body that draws no line (one joint, at its origin).
An XDMF written before the blocks existed (one grid per time, no blocks) draws its lines only.
Lines are coloured by body (a legend names the bodies, from the .h5, up to 24 of them), by
axial force with --color axial_force (strut ties, beams, super truss members, ropes), or by the
members' utilization (von Mises over the yield stress) or von Mises stress with --color
utilization / von_mises (grey where a member has none); joints take their body's colour, or grey.
Every picture and frame carries the model's title (--title replaces it), the simulated time and
the x, y, z axes, and one colour range holds for all times drawn: the largest |axial force| over
them (or --range), the full range of body indices for --color body.
ParaView's XDMF reader reports "Cannot find DataItem element in geometry xml, no caching
possible" on every read of a step (docs/output-format.md): harmless, so it is dropped here; any
other message of the reader is passed on to stderr.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ElementTree

from paraview.simple import (ColorBy, CreateView, ExtractBlock, ExtractSurface, ForceTime,
                             GetColorTransferFunction, GetScalarBar, Glyph, MergeBlocks, Render,
                             SaveScreenshot, Show, Text, Tube, XDMFReader)
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.vtkConstants import VTK_STRING
from vtkmodules.vtkCommonCore import vtkCommand

# Where the camera stands, seen from the model's centre, and which way is up.
DIRECTIONS = {"xz": ((0, -1, 0), (0, 0, 1)), "yz": ((1, 0, 0), (0, 0, 1)),
              "xy": ((0, 0, 1), (0, 1, 0)), "iso": ((1, -1.4, 0.8), (0, 0, 1))}
HARMLESS = "Cannot find DataItem element in geometry xml"
# Joint spheres against member tubes: large enough to show a lone joint, small enough not to
# hide the lattice around a node.
SPHERE_TO_TUBE = 2.0
DARK = [0.1, 0.1, 0.1]


def open_results(path):
    """The XDMF reader of `path`, its harmless cache message silenced (see the module's docstring)."""
    reader = XDMFReader(FileNames=[path])

    @calldata_type(VTK_STRING)
    def on_error(_obj, _event, text):
        if HARMLESS not in text:
            sys.stderr.write(text)

    # The proxy's reader is a file-series wrapper; the XDMF reader inside raises the messages.
    # An error observer on it takes them instead of VTK's output window.
    reader.GetClientSideObject().GetReader().AddObserver(vtkCommand.ErrorEvent, on_error)
    reader.UpdatePipeline()
    return reader


def model_title(path):
    """The name of the XDMF's outer grid (the model's title, or the results' base name when the
    model has none), or the file's stem if it is empty."""
    for _, element in ElementTree.iterparse(path, events=("start",)):
        if element.tag == "Grid":
            return element.get("Name") or os.path.splitext(os.path.basename(path))[0]
    return os.path.splitext(os.path.basename(path))[0]


def bare(name):
    """An array name without its unit: "axial_force [N]" -> "axial_force"."""
    return re.sub(r"\s*\[[^\]]*\]$", "", name)


class Parts:
    """The pipeline of one drawn time: the reader forced to that time, its members (line cells)
    and its joints (vertices; None for an XDMF without blocks)."""

    def __init__(self, reader, blocks, t):
        self.at = ForceTime(Input=reader, IgnorePipelineTime=1, ForcedTime=t)
        if blocks:
            self.members = MergeBlocks(Input=ExtractBlock(Input=self.at, Selectors=["/Root/members"]))
            self.joints = MergeBlocks(Input=ExtractBlock(Input=self.at, Selectors=["/Root/joints"]))
        else:
            self.members, self.joints = self.at, None

    def update(self, t):
        self.at.ForcedTime = t
        for part in (self.members, self.joints):
            if part is not None:
                part.UpdatePipeline(t)

    def bounds(self):
        b = list(self.members.GetDataInformation().GetBounds())
        if self.joints is not None:
            j = self.joints.GetDataInformation().GetBounds()
            b = [min(b[i], j[i]) if i % 2 == 0 else max(b[i], j[i]) for i in range(6)]
        return b

    def array(self, wanted):
        """The members' cell array called `wanted`, with or without a unit in its name."""
        names = [n for n in self.members.CellData.keys() if bare(n) == wanted]
        if not names:
            sys.exit(f"render.py: the results have no cell array '{wanted}'")
        return names[0]


def survey(reader, blocks, times, a):
    """Bounds of the model over `times` and the colour range that holds for all of them."""
    parts = Parts(reader, blocks, times[0])
    lo, hi, force = [1e300] * 3, [-1e300] * 3, 0.0
    array = parts.array(a.color)
    for t in times:
        parts.update(t)
        b = parts.bounds()
        lo = [min(lo[i], b[2 * i]) for i in range(3)]
        hi = [max(hi[i], b[2 * i + 1]) for i in range(3)]
        if a.color != "body":
            r = parts.members.CellData[array].GetRange()
            force = max(force, abs(r[0]), abs(r[1]))
    bounds = [v for i in range(3) for v in (lo[i], hi[i])]
    if a.color != "body":
        limit = a.range if a.range else (force if force > 0 else 1.0)
        # Stresses and utilizations are magnitudes: 0..max; forces -max..max.
        return bounds, (-limit, limit) if a.color == "axial_force" else (0.0, limit)
    # Body indices do not change over time: the members' and the joints' together.
    ranges = [parts.members.CellData[array].GetRange()]
    if parts.joints is not None and "body" in parts.joints.PointData.keys():
        ranges.append(parts.joints.PointData["body"].GetRange())
    return bounds, (min(r[0] for r in ranges), max(r[1] for r in ranges))


def body_names(xdmf):
    """The model's body names by index, from the .h5 the XDMF reads (/model/body_names); an
    empty list when h5py or the file is missing (the legend then shows indices)."""
    try:
        import h5py
    except ImportError:
        return []
    for _, element in ElementTree.iterparse(xdmf, events=("start",)):
        if element.tag == "DataItem" and element.get("Format") == "HDF" and element.text:
            h5 = os.path.join(os.path.dirname(os.path.abspath(xdmf)), element.text.strip().split(":")[0])
            try:
                with h5py.File(h5, "r") as f:
                    return [n.decode() if isinstance(n, bytes) else str(n) for n in f["model/body_names"][()]]
            except (OSError, KeyError):
                return []
    return []


# A legend of body names is drawn up to this many bodies; beyond, it would cover the picture.
MAX_LEGEND_BODIES = 24


def colour_map(view, a, span):
    """The colour map all displays share, fixed to `span`, with a legend: body names (up to
    MAX_LEGEND_BODIES bodies) or the axial force's scale."""
    lut = GetColorTransferFunction(a.color)
    lut.AutomaticRescaleRangeMode = "Never"
    if a.color == "body":
        # Categories, one per body index: neighbouring bodies (boom sections) differ clearly,
        # which a continuous map over 17 bodies would not give. The palette's 9 colours repeat
        # (ParaView draws indices past the last colour in the NaN colour).
        lut.ApplyPreset("Brewer Qualitative Set1", True)
        bodies = range(int(span[0]), int(span[1]) + 1)
        palette = [lut.IndexedColors[i:i + 3] for i in range(0, len(lut.IndexedColors), 3)]
        names = body_names(a.xdmf)
        lut.Annotations = [v for b in bodies for v in (str(b), names[b] if b < len(names) else str(b))]
        lut.IndexedColors = [c for k in range(len(bodies)) for c in palette[k % len(palette)]]
        if len(bodies) <= MAX_LEGEND_BODIES:
            bar = GetScalarBar(lut, view)
            bar.Title = "body"
            bar.ComponentTitle = ""
            bar.TitleColor = bar.LabelColor = DARK
        return lut
    lut.ApplyPreset("Cool to Warm" if a.color == "axial_force" else "Inferno (matplotlib)", True)
    lut.RescaleTransferFunction(span[0], span[1])
    lut.NanColor = [0.6, 0.6, 0.6]  # members without the quantity (ropes without a yield stress)
    bar = GetScalarBar(lut, view)
    bar.Title = {"axial_force": "axial force [N]", "utilization": "utilization",
                 "von_mises": "von Mises stress [Pa]"}[a.color]
    bar.ComponentTitle = ""
    bar.TitleColor = bar.LabelColor = DARK
    return lut


def lut_has_legend(a):
    """Whether the body colours get a legend (few enough bodies, see colour_map)."""
    lo, hi = a.span
    return a.color == "body" and hi - lo + 1 <= MAX_LEGEND_BODIES


def draw(parts, view, a, radius):
    """Shows the members as tubes and the joints as spheres; returns their displays."""
    # The members are an unstructured grid; tubes need poly data.
    tubes = Tube(Input=ExtractSurface(Input=parts.members), Radius=radius, NumberofSides=12)
    shown = [Show(tubes, view)]
    array = parts.array(a.color)
    ColorBy(shown[0], ("CELLS", array))
    if a.color != "body" or lut_has_legend(a):
        shown[0].SetScalarBarVisibility(view, True)
    if parts.joints is not None:
        spheres = Glyph(Input=parts.joints, GlyphType="Sphere", GlyphMode="All Points",
                        ScaleArray=["POINTS", "No scale array"], ScaleFactor=2 * SPHERE_TO_TUBE * radius)
        spheres.GlyphType.ThetaResolution = 16
        spheres.GlyphType.PhiResolution = 12
        d = Show(spheres, view)
        if a.color == "body":
            ColorBy(d, ("POINTS", "body"))
        else:
            ColorBy(d, None)
            d.AmbientColor = d.DiffuseColor = [0.6, 0.6, 0.6]
        shown.append(d)
    return shown


def caption(view, a):
    """The dark text at the view's upper left corner, the title over the time (one text, so the
    two cannot overlap however small the picture); returns its source, whose Text the caller sets."""
    source = Text()
    d = Show(source, view)
    d.WindowLocation = "Upper Left Corner"
    d.Justification = "Left"
    d.FontSize = max(10, a.size[1] // 40)
    d.Color = DARK
    return source


def decimals(times):
    """The fewest decimals (at most 6) that write every time exactly, so a movie's time label
    keeps one width from frame to frame."""
    for d in range(7):
        if all(abs(round(t, d) - t) <= 1e-9 * max(1.0, abs(t)) for t in times):
            return d
    return 6


def place_camera(view, bounds, direction):
    """Looks at `bounds` from `direction`; call it once everything is shown."""
    # paraview.simple resets the camera to what is shown at a view's first render: render once
    # before, so that the camera set here stays.
    Render(view)
    extent = max(bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4], 1e-3)
    camera = view.GetActiveCamera()
    cx, cy, cz = [(bounds[2 * i] + bounds[2 * i + 1]) / 2 for i in range(3)]
    (dx, dy, dz), up = DIRECTIONS[direction]
    norm = (dx * dx + dy * dy + dz * dz) ** 0.5
    camera.SetFocalPoint(cx, cy, cz)
    camera.SetPosition(cx + dx / norm * 10 * extent, cy + dy / norm * 10 * extent, cz + dz / norm * 10 * extent)
    camera.SetViewUp(*up)
    view.ResetCamera(bounds)
    # A margin that keeps the model clear of the title and the time label.
    camera.Zoom(0.85)


def make_view(a):
    """A new white view (a PNG and a movie of one call do not share one) with dark-lettered
    x, y, z axes."""
    view = CreateView("RenderView")
    view.ViewSize = a.size
    view.UseColorPaletteForBackground = 0
    view.Background = [1, 1, 1]
    view.OrientationAxesVisibility = 1
    view.OrientationAxesLabelColor = DARK
    return view


def tube_radius(a, bounds):
    extent = max(bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4], 1e-3)
    return a.radius if a.radius > 0 else 0.006 * extent


def picture(reader, blocks, steps, a):
    wanted = a.times if a.times else [steps[-1]]
    nearest = [min(steps, key=lambda s: abs(s - t)) for t in wanted]
    bounds, span = survey(reader, blocks, nearest, a)
    a.span = span
    view = make_view(a)
    radius = tube_radius(a, bounds)
    for k, t in enumerate(nearest):
        parts = Parts(reader, blocks, t)
        for d in draw(parts, view, a, radius):
            # Earlier times lighter so a sequence reads as a motion.
            d.Opacity = 0.25 + 0.75 * (k + 1) / len(nearest)
    places = decimals(nearest)
    times = ", ".join(f"{t:.{places}f}" for t in nearest)
    later = " (later darker)" if len(nearest) > 1 else ""
    caption(view, a).Text = f"{a.title}\nt = {times} s{later}"
    colour_map(view, a, span)
    place_camera(view, bounds, a.view)
    Render(view)
    SaveScreenshot(a.output, view, ImageResolution=a.size)
    print(f"wrote {a.output} ({len(wanted)} time(s) of {len(steps)})")


def movie(reader, blocks, steps, a):
    if shutil.which("ffmpeg") is None:
        sys.exit("render.py: --movie needs ffmpeg (Debian package ffmpeg)")
    count = min(len(steps), max(1, a.frames))
    frames = [steps[round(i * (len(steps) - 1) / max(1, count - 1))] for i in range(count)]
    bounds, span = survey(reader, blocks, frames, a)
    a.span = span
    view = make_view(a)
    parts = Parts(reader, blocks, frames[0])
    draw(parts, view, a, tube_radius(a, bounds))
    colour_map(view, a, span)
    places = decimals(frames)
    text = caption(view, a)
    place_camera(view, bounds, a.view)
    work = tempfile.mkdtemp(prefix="latticedyn_movie_")
    try:
        for i, t in enumerate(frames):
            parts.at.ForcedTime = t
            text.Text = f"{a.title}\nt = {t:.{places}f} s"
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
    p.add_argument("--color", default="body", choices=["body", "axial_force", "utilization", "von_mises"])
    # one positive number: pvpython takes a negative argument for one of its own options
    p.add_argument("--range", type=float, default=None, metavar="MAX",
                   help="colour range -MAX..MAX for --color axial_force, 0..MAX for utilization and von_mises (default: the largest value "
                        "over the times drawn; a fixed one compares two runs)")
    p.add_argument("--title", default=None, help="title on the pictures (default: the model's title)")
    p.add_argument("--size", type=int, nargs=2, default=[1200, 800])
    p.add_argument("--radius", type=float, default=0.0,
                   help="tube radius in model units (0: a fraction of the model size); joints twice it")
    a = p.parse_args()
    if not a.output and not a.movie:
        p.error("give --output (PNG) or --movie (MP4)")
    if not os.path.isfile(a.xdmf):
        sys.exit(f"render.py: no file {a.xdmf}")
    if a.title is None:
        a.title = model_title(a.xdmf)

    reader = open_results(a.xdmf)
    # Results with blocks (members, joints, constraints) read as a multiblock data set; older
    # ones as one unstructured grid per time.
    blocks = reader.GetDataInformation().IsCompositeDataSet()
    steps = list(reader.TimestepValues) if reader.TimestepValues else [0.0]
    if a.output:
        picture(reader, blocks, steps, a)
    if a.movie:
        movie(reader, blocks, steps, a)


if __name__ == "__main__":
    main()
