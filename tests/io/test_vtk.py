"""VTK export: valid XML that a VTK reader parses, the right counts, the container moving with the drive."""

import xml.etree.ElementTree as ET

import numpy as np
import pytest

from pdamper.geometry import Cuboid, Cylinder
from pdamper.io.vtk import polydata_xml, pvd_xml, write_case_vtk, write_vtk_series
from pdamper.params import Case, ParticleSet


def _traj(frames=4, n=3):
    t = (np.arange(frames) + 1) * 0.01
    pos = np.zeros((frames, n, 3))
    pos[:, :, 0] = np.linspace(-0.02, 0.02, n)
    pos[:, :, 1] = 0.005
    vel = np.zeros_like(pos)
    vel[:, :, 0] = 0.1
    spin = np.zeros_like(pos)
    spin[:, :, 2] = -20.0
    return {"time": t, "position": pos, "velocity": vel, "spin": spin, "radius": np.full(n, 0.005)}


def _arrays(piece):
    return {a.get("Name"): np.array((a.text or "").split(), dtype=float) for a in piece.iter("DataArray")}


def test_polydata_is_valid_vtk_xml_with_counts_and_arrays():
    doc = ET.fromstring(polydata_xml(np.eye(3), verts=True, point_data={"radius": np.ones(3), "velocity": np.eye(3)}))
    assert doc.tag == "VTKFile" and doc.get("type") == "PolyData"
    piece = doc.find("PolyData/Piece")
    assert piece.get("NumberOfPoints") == "3" and piece.get("NumberOfVerts") == "3" and piece.get("NumberOfPolys") == "0"
    arr = _arrays(piece)
    assert arr["Points"].size == 9 and arr["radius"].size == 3 and arr["velocity"].size == 9
    verts = piece.find("Verts")
    conn = [a for a in verts.iter("DataArray") if a.get("Name") == "connectivity"][0]
    offs = [a for a in verts.iter("DataArray") if a.get("Name") == "offsets"][0]
    assert conn.text.split() == ["0", "1", "2"] and offs.text.split() == ["1", "2", "3"]


def test_pvd_indexes_the_frames_by_time():
    doc = ET.fromstring(pvd_xml([(0.01, "a.vtp"), (0.02, "b.vtp")]))
    sets = doc.findall("Collection/DataSet")
    assert doc.get("type") == "Collection" and [d.get("file") for d in sets] == ["a.vtp", "b.vtp"]
    assert [float(d.get("timestep")) for d in sets] == [0.01, 0.02]


def test_series_moves_particles_and_container_with_the_drive(tmp_path):
    tr = _traj()
    box = Cuboid()
    xc = np.array([0.0, 0.001, 0.002, 0.003])
    vc = np.array([0.5, 0.4, 0.3, 0.2])
    info = write_vtk_series(tmp_path, tr, mesh=box.mesh(), drive_position=xc, drive_velocity=vc,
                            drive_dir=(1.0, 0.0, 0.0))
    assert info["frames"] == 4
    pvd = ET.parse(info["particles"]).getroot()
    files = [d.get("file") for d in pvd.iter("DataSet")]
    assert len(files) == 4 and all((tmp_path / f).is_file() for f in files)
    last = ET.parse(tmp_path / files[-1]).getroot().find("PolyData/Piece")
    arr = _arrays(last)
    pts = arr["Points"].reshape(-1, 3)
    np.testing.assert_allclose(pts[:, 0], tr["position"][-1, :, 0] + 0.003)          # lab frame
    np.testing.assert_allclose(arr["velocity"].reshape(-1, 3)[:, 0], 0.1 + 0.2)      # lab velocity
    np.testing.assert_allclose(arr["spin"].reshape(-1, 3)[:, 2], -20.0)
    np.testing.assert_allclose(arr["radius"], 0.005)
    cont = [d.get("file") for d in ET.parse(info["container"]).getroot().iter("DataSet")]
    piece = ET.parse(tmp_path / cont[-1]).getroot().find("PolyData/Piece")
    assert piece.get("NumberOfPoints") == "8" and piece.get("NumberOfPolys") == "6"
    cpts = _arrays(piece)["Points"].reshape(-1, 3)
    assert cpts[:, 0].min() == pytest.approx(-0.06 + 0.003) and cpts[:, 0].max() == pytest.approx(0.06 + 0.003)


def test_case_series_of_a_cylinder_keeps_the_last_cycles(tmp_path):
    from pdamper.params import Container

    case = Case(particles=(ParticleSet(count=3),), container=Container(geometry=Cylinder()))
    tr = _traj(frames=100)
    tr["time"] = (np.arange(100) + 1) * 0.01   # 1 s = 2 cycles at 2 Hz
    info = write_case_vtk(tmp_path, tr, case, cycles=1)
    assert info["frames"] == 51
    cont = [d.get("file") for d in ET.parse(info["container"]).getroot().iter("DataSet")]
    piece = ET.parse(tmp_path / cont[0]).getroot().find("PolyData/Piece")
    assert piece.get("NumberOfPolys") == "48"   # the side wall as 48 quads
