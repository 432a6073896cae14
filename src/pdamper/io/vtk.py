"""VTK export of a trajectory for ParaView: particles and the moving container as a time series.

:func:`write_vtk_series` writes, into one directory,

- ``particles_NNNNN.vtp`` -- one VTK XML PolyData file per frame: the sphere centres as points
  (vertices) with point data ``radius`` [m], ``velocity`` [m/s] and ``spin`` [rad/s] (lab
  frame velocity: the container-frame velocity plus the container's), ``id``;
- ``container_NNNNN.vtp`` -- the container's inner surface as quads at its position in that
  frame (a cuboid's six faces, a cylinder's side wall);
- ``particles.pvd``, ``container.pvd`` -- the ParaView collection files that index the frames
  by time [s]; open them in ParaView (File > Open, both files) and press Play. Show the
  particles with the "Point Gaussian" representation and "Scale by" ``radius`` (Gaussian
  radius 1, "Use Scale Array"), or with a Glyph filter (sphere, scale by ``radius``, factor 2).

Coordinates are in the **lab frame** [m]: the container frame (x along the container, y up)
moved by the drive, ``x_lab = x + x_c(t) d``, d the drive direction in the container frame; the
small mounting tilt is not applied (the container frame is what the engine integrates in).

The files are ASCII VTK XML (``<VTKFile type="PolyData" version="1.0">``), written with numpy
alone; the ``.pvd`` indexes are written last and atomically, so a complete index means complete
frames.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .files import atomic_write

__all__ = ["write_vtk_series", "write_case_vtk", "polydata_xml", "pvd_xml"]


def _array(name, values, components=1, dtype="Float64"):
    flat = np.asarray(values).reshape(-1)
    if dtype.startswith("Float"):
        body = " ".join(f"{v:.9g}" for v in flat)
    else:
        body = " ".join(str(int(v)) for v in flat)
    comp = f' NumberOfComponents="{components}"' if components > 1 else ""
    return f'        <DataArray type="{dtype}" Name="{name}"{comp} format="ascii">{body}</DataArray>\n'


def polydata_xml(points, *, verts: bool = False, polys=None, point_data: dict | None = None) -> str:
    """One VTK XML PolyData document: ``points`` (P, 3); each point a vertex cell if ``verts``;
    ``polys`` a list of index arrays (polygons); ``point_data`` name -> (P,) or (P, 3) array."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    npts = pts.shape[0]
    polys = [] if polys is None else [np.asarray(p, dtype=np.int64) for p in polys]
    out = ['<?xml version="1.0"?>\n',
           '<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian" header_type="UInt64">\n',
           '  <PolyData>\n',
           f'    <Piece NumberOfPoints="{npts}" NumberOfVerts="{npts if verts else 0}" NumberOfLines="0" '
           f'NumberOfStrips="0" NumberOfPolys="{len(polys)}">\n']
    if point_data:
        scalars = next((k for k, v in point_data.items() if np.asarray(v).ndim == 1), None)
        vectors = next((k for k, v in point_data.items() if np.asarray(v).ndim == 2), None)
        attrs = (f' Scalars="{scalars}"' if scalars else "") + (f' Vectors="{vectors}"' if vectors else "")
        out.append(f"      <PointData{attrs}>\n")
        for name, v in point_data.items():
            v = np.asarray(v)
            kind = "Int64" if np.issubdtype(v.dtype, np.integer) else "Float64"
            out.append(_array(name, v, 3 if v.ndim == 2 else 1, kind))
        out.append("      </PointData>\n")
    out.append("      <Points>\n")
    out.append(_array("Points", pts, 3))
    out.append("      </Points>\n")
    for tag, cells in (("Verts", [np.array([i]) for i in range(npts)] if verts else []), ("Polys", polys)):
        out.append(f"      <{tag}>\n")
        conn = np.concatenate(cells) if cells else np.zeros(0, dtype=np.int64)
        offs = np.cumsum([len(c) for c in cells]) if cells else np.zeros(0, dtype=np.int64)
        out.append(_array("connectivity", conn, dtype="Int64"))
        out.append(_array("offsets", offs, dtype="Int64"))
        out.append(f"      </{tag}>\n")
    out.append("    </Piece>\n  </PolyData>\n</VTKFile>\n")
    return "".join(out)


def pvd_xml(entries) -> str:
    """A ParaView collection: ``entries`` is a list of (time [s], file name)."""
    rows = "".join(f'    <DataSet timestep="{t:.9g}" group="" part="0" file="{f}"/>\n' for t, f in entries)
    return ('<?xml version="1.0"?>\n<VTKFile type="Collection" version="1.0" byte_order="LittleEndian">\n'
            f"  <Collection>\n{rows}  </Collection>\n</VTKFile>\n")


def write_vtk_series(out_dir, trajectory: dict, *, mesh, drive_position=None, drive_velocity=None, drive_dir=None,
                     offsets=None) -> dict:
    """Write the VTK time series of ``trajectory`` (container frame: ``time``, ``position``,
    ``velocity``, ``spin``, ``radius``) into ``out_dir``.

    ``mesh``: (vertices (V, 3), quads (Q, 4)) of the container in its frame; ``drive_position``,
    ``drive_velocity``: the container's x_c [m] and v_c [m/s] at each frame; ``drive_dir``: the
    drive direction in the container frame; or instead ``offsets``: (displacement (F, 3) [m],
    velocity (F, 3) [m/s]) of the container at each frame. Returns ``{"particles": pvd path, "container": pvd
    path, "frames": F}``.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    t = np.asarray(trajectory["time"], dtype=float)
    pos = np.asarray(trajectory["position"], dtype=float)
    vel = np.asarray(trajectory["velocity"], dtype=float)
    spin = np.asarray(trajectory["spin"], dtype=float)
    rad = np.broadcast_to(np.asarray(trajectory["radius"], dtype=float), pos.shape[1])
    if offsets is not None:
        shifts, cvel = (np.asarray(a, dtype=float) for a in offsets)
    else:
        d = np.asarray(drive_dir, dtype=float)
        shifts = np.outer(np.asarray(drive_position, dtype=float), d)
        cvel = np.outer(np.asarray(drive_velocity, dtype=float), d)
    verts, quads = mesh
    ids = np.arange(pos.shape[1], dtype=np.int64)
    width = max(5, len(str(len(t))))
    for pattern in ("particles_*.vtp", "container_*.vtp"):  # frames of an earlier, longer export
        for stale in out.glob(pattern):
            stale.unlink()
    p_entries, c_entries = [], []
    for k in range(len(t)):
        shift = shifts[k]
        pname = f"particles_{k:0{width}d}.vtp"
        cname = f"container_{k:0{width}d}.vtp"
        (out / pname).write_text(polydata_xml(pos[k] + shift, verts=True, point_data={
            "radius": rad, "velocity": vel[k] + cvel[k], "spin": spin[k], "id": ids}), encoding="utf-8")
        (out / cname).write_text(polydata_xml(np.asarray(verts) + shift, polys=list(quads)), encoding="utf-8")
        p_entries.append((t[k], pname))
        c_entries.append((t[k], cname))
    atomic_write(out / "particles.pvd", pvd_xml(p_entries).encode())
    atomic_write(out / "container.pvd", pvd_xml(c_entries).encode())
    return {"particles": str(out / "particles.pvd"), "container": str(out / "container.pvd"), "frames": len(t)}


def write_case_vtk(out_dir, trajectory: dict, case, *, cycles: float | None = None) -> dict:
    """:func:`write_vtk_series` for a trajectory of ``case`` (a :class:`pdamper.params.Case`):
    the container mesh from the case, its motion from the trajectory's recorded pose (or the
    case's drive). ``cycles``: only the last ``cycles`` drive cycles."""
    from ..geometry.track import container_track

    t = np.asarray(trajectory["time"], dtype=float)
    keep = np.ones(t.size, dtype=bool)
    f = float(case.drive.frequency or 0.0)
    if cycles is not None and f > 0:
        keep = t >= t[-1] - cycles / f - 1e-12
    off, vel, _ = container_track(trajectory, case)
    traj = {k: (np.asarray(v)[keep] if k != "radius" else v) for k, v in trajectory.items()}
    return write_vtk_series(out_dir, traj, mesh=case.container.geometry.mesh(), offsets=(off[keep], vel[keep]))
