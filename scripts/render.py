"""Renders latticedyn results (the .xdmf beside the .h5) to PNG with ParaView, for docs and quick looks.

Run with ParaView's Python, under a virtual X display on a headless machine:

    xvfb-run -a pvpython scripts/render.py results/double_pendulum/double_pendulum.xdmf \
        --output docs/images/double_pendulum.png --times 0 0.5 1.0 --view xz

Several times are drawn over each other, later ones darker, to show a motion in one picture.
Lines are coloured by body, or by axial force with --color axial_force (strut ties, beams).
"""
import argparse

from paraview.simple import (ColorBy, ExtractSurface, ForceTime, GetActiveViewOrCreate,
                             GetColorTransferFunction, GetScalarBar, Render, SaveScreenshot, Show, Tube,
                             XDMFReader)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("xdmf")
    p.add_argument("--output", required=True, help="PNG file to write")
    p.add_argument("--times", type=float, nargs="*", default=None,
                   help="simulated times to draw (default: the last one)")
    p.add_argument("--view", default="xz", choices=["xz", "yz", "xy", "iso"],
                   help="viewing plane (x right, z up for xz)")
    p.add_argument("--color", default="body", choices=["body", "axial_force"])
    # one positive number: pvpython takes a negative argument for one of its own options
    p.add_argument("--range", type=float, default=None, metavar="MAX",
                   help="colour range -MAX..MAX for --color axial_force (to compare two runs)")
    p.add_argument("--size", type=int, nargs=2, default=[1200, 800])
    p.add_argument("--radius", type=float, default=0.0,
                   help="tube radius in model units (0: a fraction of the model size)")
    a = p.parse_args()

    reader = XDMFReader(FileNames=[a.xdmf])
    reader.UpdatePipeline()
    steps = list(reader.TimestepValues) if reader.TimestepValues else [0.0]
    wanted = a.times if a.times else [steps[-1]]
    view = GetActiveViewOrCreate("RenderView")
    view.ViewSize = a.size
    view.UseColorPaletteForBackground = 0
    view.Background = [1, 1, 1]
    view.OrientationAxesVisibility = 1

    bounds = reader.GetDataInformation().GetBounds()
    extent = max(bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4], 1e-3)
    radius = a.radius if a.radius > 0 else 0.006 * extent
    for k, t in enumerate(wanted):
        nearest = min(steps, key=lambda s: abs(s - t))
        one = ForceTime(Input=reader, IgnorePipelineTime=1, ForcedTime=nearest)
        # The XDMF reader gives an unstructured grid; tubes need poly data.
        tube = Tube(Input=ExtractSurface(Input=one), Radius=radius, NumberofSides=12)
        d = Show(tube, view)
        if a.color == "axial_force":
            ColorBy(d, ("CELLS", "axial_force"))
            d.SetScalarBarVisibility(view, True)
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
            ColorBy(d, ("CELLS", "body"))
            GetColorTransferFunction("body").ApplyPreset("Set1", True)
        # Earlier times lighter so a sequence reads as a motion.
        d.Opacity = 0.25 + 0.75 * (k + 1) / len(wanted)

    camera = view.GetActiveCamera()
    cx, cy, cz = [(bounds[2 * i] + bounds[2 * i + 1]) / 2 for i in range(3)]
    # Where the camera stands, seen from the model's centre, and which way is up.
    directions = {"xz": ((0, -1, 0), (0, 0, 1)), "yz": ((1, 0, 0), (0, 0, 1)),
                  "xy": ((0, 0, 1), (0, 1, 0)), "iso": ((1, -1.4, 0.8), (0, 0, 1))}
    (dx, dy, dz), up = directions[a.view]
    norm = (dx * dx + dy * dy + dz * dz) ** 0.5
    camera.SetFocalPoint(cx, cy, cz)
    camera.SetPosition(cx + dx / norm * 10 * extent, cy + dy / norm * 10 * extent, cz + dz / norm * 10 * extent)
    camera.SetViewUp(*up)
    view.ResetCamera()
    Render(view)
    SaveScreenshot(a.output, view, ImageResolution=a.size)
    print(f"wrote {a.output} ({len(wanted)} time(s) of {len(steps)})")


if __name__ == "__main__":
    main()
