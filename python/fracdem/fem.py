"""Readers for fix fem/body energy histories (CSV) and fix fem/vtk ParaView output (.pvd/.vtu)."""
import os
import xml.etree.ElementTree as ET

import numpy as np
import pandas as pd

ENERGY_COLUMNS = ["step", "time", "kinetic", "strain", "external_work", "contact_work", "total", "nodes", "elements"]
# The material's dissipation column: named after what dissipates (cracking or plastic flow).
DISSIPATION_COLUMNS = ("fracture_energy", "plastic_work")


def read_energy(path):
    """Energy history written by `fix fem/body ... energy_file FILE N`."""
    df = pd.read_csv(path)
    missing = [c for c in ENERGY_COLUMNS if c not in df.columns]
    if missing:
        raise ValueError(f"{path}: not a fem/body energy file, missing columns {missing}")
    return df


def fracture_summary(df, group, component="x"):
    """Peak reaction of a fixed / prescribed_velocity group, the group's displacement there, and the
    energy dissipated by cracking, split nodes and fragments at the end of a fem/body energy file."""
    r, u = f"reaction_{group}_{component}", f"displacement_{group}_{component}"
    if r not in df or u not in df:
        groups = sorted({c.split("_", 1)[1].rsplit("_", 1)[0] for c in df if c.startswith("reaction_")})
        raise KeyError(f"energy file has no group {group!r} (groups: {groups})")
    load = df[r].abs()
    k = int(load.idxmax())
    dissipation = next((c for c in DISSIPATION_COLUMNS if c in df), None)
    if dissipation is None:
        raise KeyError(f"energy file has none of the dissipation columns {list(DISSIPATION_COLUMNS)}")
    return {"peak_load": float(load[k]), "displacement_at_peak": float(df[u][k]),
            "dissipation_column": dissipation, "dissipated": float(df[dissipation].iloc[-1]),
            "split_nodes": int(df["split_nodes"].iloc[-1]), "fragments": int(df["fragments"].iloc[-1])}


def read_pvd(path):
    """List of (time, absolute .vtu path) from a ParaView .pvd series index."""
    base = os.path.dirname(os.path.abspath(path))
    root = ET.parse(path).getroot()
    out = []
    for ds in root.iter("DataSet"):
        out.append((float(ds.get("timestep")), os.path.normpath(os.path.join(base, ds.get("file")))))
    return out


def read_vtu(path):
    """Points, cells and data arrays of a .vtu file as numpy arrays (needs `vtk` or `meshio`)."""
    try:
        import vtk
        from vtk.util.numpy_support import vtk_to_numpy
    except ImportError:
        vtk = None
    if vtk is not None:
        r = vtk.vtkXMLUnstructuredGridReader()
        r.SetFileName(path)
        r.Update()
        g = r.GetOutput()
        pd_ = g.GetPointData()
        cd = g.GetCellData()
        cells = [[g.GetCell(i).GetPointId(k) for k in range(g.GetCell(i).GetNumberOfPoints())]
                 for i in range(g.GetNumberOfCells())]
        return {
            "points": vtk_to_numpy(g.GetPoints().GetData()),
            "cells": cells,
            "point_data": {pd_.GetArrayName(i): vtk_to_numpy(pd_.GetArray(i)) for i in range(pd_.GetNumberOfArrays())},
            "cell_data": {cd.GetArrayName(i): vtk_to_numpy(cd.GetArray(i)) for i in range(cd.GetNumberOfArrays())},
        }
    try:
        import meshio
    except ImportError:
        raise ImportError("read_vtu needs the 'vtk' package (pip install vtk) or 'meshio' (pip install meshio)")
    m = meshio.read(path)
    return {
        "points": np.asarray(m.points),
        "cells": [list(c) for block in m.cells for c in block.data],
        "point_data": dict(m.point_data),
        "cell_data": {k: np.concatenate(v) for k, v in m.cell_data.items()},
    }
