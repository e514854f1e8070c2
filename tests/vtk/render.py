"""Renders a VTK frame of trubal off-screen with the VTK library (EGL or OSMesa, no
display) and checks that the picture is not empty: the particles as spheres scaled by their
radius (Glyph), coloured by cluster, seen through, with the contact network as tubes coloured
by the normal force; or one coarse-grained field as a slice through its middle.

    python render.py network DIR PREFIX CYCLE OUT.png
    python render.py field FILE.vti ARRAY OUT.png

Used by tests/it/vtk.rs, and to make doc/img/vtk_network.png and doc/img/vtk_field.png.
"""

import sys

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy


def window(size=(640, 480)):
    ren = vtk.vtkRenderer()
    ren.SetBackground(1, 1, 1)
    w = vtk.vtkRenderWindow()
    w.SetOffScreenRendering(1)
    w.AddRenderer(ren)
    w.SetSize(*size)
    return ren, w


def reader(path):
    r = vtk.vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    return r


def network(top, prefix, cycle):
    ren, w = window()
    name = lambda kind: f"{top}/{prefix}_{kind}_c{int(cycle):08}.vtp"
    parts = reader(name("particles")).GetOutput()
    parts.GetPointData().SetActiveScalars("radius")
    sphere = vtk.vtkSphereSource()
    sphere.SetRadius(1.0)
    sphere.SetThetaResolution(20)
    sphere.SetPhiResolution(14)
    glyph = vtk.vtkGlyph3D()
    glyph.SetInputData(parts)
    glyph.SetSourceConnection(sphere.GetOutputPort())
    glyph.SetScaleModeToScaleByScalar()
    glyph.SetColorModeToColorByScalar()
    glyph.Update()
    # Colour by cluster: the glyphs carry the input's arrays.
    out = glyph.GetOutput()
    out.GetPointData().SetActiveScalars("cluster")
    cl = vtk_to_numpy(parts.GetPointData().GetArray("cluster"))
    m = vtk.vtkPolyDataMapper()
    m.SetInputData(out)
    m.SetScalarModeToUsePointFieldData()
    m.SelectColorArray("cluster")
    m.SetScalarRange(float(cl.min()), float(cl.max()) + 1)
    a = vtk.vtkActor()
    a.SetMapper(m)
    a.GetProperty().SetOpacity(0.35)
    ren.AddActor(a)
    # The contacts as tubes coloured by the normal force.
    lines = reader(name("contacts")).GetOutput()
    fn = vtk_to_numpy(lines.GetCellData().GetArray("normal_force"))
    rmean = float(vtk_to_numpy(parts.GetPointData().GetArray("radius")).mean())
    tube = vtk.vtkTubeFilter()
    tube.SetInputData(lines)
    tube.SetRadius(0.15 * rmean)
    tube.SetNumberOfSides(10)
    tm = vtk.vtkPolyDataMapper()
    tm.SetInputConnection(tube.GetOutputPort())
    tm.SetScalarModeToUseCellFieldData()
    tm.SelectColorArray("normal_force")
    lim = float(np.abs(fn).max()) if len(fn) else 1.0
    tm.SetScalarRange(-lim, lim)
    lut = vtk.vtkLookupTable()
    lut.SetHueRange(0.667, 0.0)
    lut.Build()
    tm.SetLookupTable(lut)
    ta = vtk.vtkActor()
    ta.SetMapper(tm)
    ren.AddActor(ta)
    bar = vtk.vtkScalarBarActor()
    bar.SetLookupTable(lut)
    bar.SetTitle("normal force (N)")
    bar.GetTitleTextProperty().SetColor(0, 0, 0)
    bar.GetLabelTextProperty().SetColor(0, 0, 0)
    bar.SetNumberOfLabels(3)
    bar.SetWidth(0.1)
    ren.AddViewProp(bar)
    # The walls, seen through.
    walls = reader(name("walls")).GetOutput()
    if walls.GetNumberOfCells():
        wm = vtk.vtkPolyDataMapper()
        wm.SetInputData(walls)
        wm.ScalarVisibilityOff()
        wa = vtk.vtkActor()
        wa.SetMapper(wm)
        wa.GetProperty().SetOpacity(0.15)
        wa.GetProperty().SetColor(0.5, 0.5, 0.5)
        ren.AddActor(wa)
    ren.ResetCamera(parts.GetBounds())
    cam = ren.GetActiveCamera()
    cam.Elevation(-60)
    cam.Azimuth(30)
    cam.Zoom(1.2)
    return w


def field(path, array):
    ren, w = window()
    r = vtk.vtkXMLImageDataReader()
    r.SetFileName(path)
    r.Update()
    img = r.GetOutput()
    n = img.GetDimensions()
    voi = vtk.vtkExtractVOI()
    voi.SetInputData(img)
    voi.SetVOI(0, n[0] - 1, n[1] // 2, n[1] // 2, 0, n[2] - 1)
    geo = vtk.vtkDataSetSurfaceFilter()
    geo.SetInputConnection(voi.GetOutputPort())
    geo.Update()
    values = vtk_to_numpy(img.GetPointData().GetArray(array))
    m = vtk.vtkPolyDataMapper()
    m.SetInputConnection(geo.GetOutputPort())
    m.SetScalarModeToUsePointFieldData()
    m.SelectColorArray(array)
    m.SetScalarRange(float(values.min()), float(values.max()))
    lut = vtk.vtkLookupTable()
    lut.SetHueRange(0.667, 0.0)
    lut.Build()
    m.SetLookupTable(lut)
    a = vtk.vtkActor()
    a.SetMapper(m)
    ren.AddActor(a)
    bar = vtk.vtkScalarBarActor()
    bar.SetLookupTable(m.GetLookupTable())
    bar.SetTitle(array)
    bar.GetTitleTextProperty().SetColor(0, 0, 0)
    bar.GetLabelTextProperty().SetColor(0, 0, 0)
    bar.SetWidth(0.1)
    ren.AddViewProp(bar)
    ren.ResetCamera()
    cam = ren.GetActiveCamera()
    cam.Elevation(-90)
    cam.OrthogonalizeViewUp()
    return w


def save_and_check(w, out):
    w.Render()
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(w)
    grab.Update()
    px = vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars())
    drawn = (px[:, :3] < 250).any(axis=1).mean()
    colours = len(np.unique(px[:, :3] // 32, axis=0))
    png = vtk.vtkPNGWriter()
    png.SetFileName(out)
    png.SetInputConnection(grab.GetOutputPort())
    png.Write()
    if drawn < 0.02 or colours < 4:
        print(f"render check failed: {drawn:.3%} of the pixels drawn, {colours} colours")
        sys.exit(1)
    print(f"render check passed: {drawn:.1%} of the pixels drawn, {colours} colours, {out}")


if sys.argv[1] == "network":
    save_and_check(network(*sys.argv[2:5]), sys.argv[5])
else:
    save_and_check(field(sys.argv[2], sys.argv[3]), sys.argv[4])
