"""Tests of the fracdem Python package: log parsing, energy/pvd/vtu readers, plots, CLI, mesh generator."""
import os
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

import fracdem
from fracdem import meshgen

LOG = """LIGGGHTS (Version LIGGGHTS-PUBLIC 3.8.0)
fix fem/body b: stable FE time step 1e-05, host time step 1e-06 (10.0%)
    Step    Atoms         KinEng       f_body[1]
       0        0              0              0
     100       10            0.5           0.25
WARNING: something odd (./src/x.cpp:1)
     200       10           0.75           0.5
Loop time of 1.234 on 2 procs for 200 steps with 10 atoms

    Step    Atoms         KinEng       f_body[1]
     200       10           0.75            0.6
     300       11            1.5            0.7
Loop time of 2.5 on 2 procs for 100 steps with 11 atoms
"""


def write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return str(p)


def test_log_runs_loop_times_and_dedup(tmp_path):
    log = fracdem.read_log(write(tmp_path, "log", LOG))
    assert len(log.runs) == 2
    assert list(log.runs[0]["Step"]) == [0, 100, 200]
    assert log.loop_times == [1.234, 2.5]
    assert log.nprocs == 2
    assert len(log.warnings) == 1
    th = log.thermo
    assert list(th["Step"]) == [0, 100, 200, 300]
    assert th.loc[th["Step"] == 200, "f_body[1]"].item() == 0.6  # later run wins


def test_truncated_log_and_errors(tmp_path):
    text = LOG.split("Loop time of 2.5")[0] + "ERROR: fix fem/body: bad (x.cpp:1)\n"
    log = fracdem.read_log(write(tmp_path, "log", text))
    assert len(log.runs) == 2 and list(log.runs[1]["Step"]) == [200, 300]
    with pytest.raises(fracdem.LogError, match="fix fem/body: bad"):
        fracdem.read_log(write(tmp_path, "log2", text), check_errors=True)


def test_energy_csv_and_pvd(tmp_path):
    df = pd.DataFrame({c: [0.0, 1.0] for c in fracdem.fem.ENERGY_COLUMNS})
    path = tmp_path / "e.csv"
    df.to_csv(path, index=False)
    back = fracdem.read_energy(str(path))
    assert back.equals(df)
    (tmp_path / "sub").mkdir()
    pvd = write(tmp_path, "sub/body.pvd", '<VTKFile type="Collection"><Collection>'
                '<DataSet timestep="0.5" file="f/b_1.vtu"/><DataSet timestep="1" file="f/b_2.vtu"/>'
                "</Collection></VTKFile>")
    entries = fracdem.read_pvd(pvd)
    assert [t for t, _ in entries] == [0.5, 1.0]
    assert entries[1][1] == os.path.join(str(tmp_path), "sub", "f", "b_2.vtu")


def test_read_vtu(tmp_path):
    pytest.importorskip("vtk")
    text = """<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="0.1"><UnstructuredGrid><Piece NumberOfPoints="4" NumberOfCells="1">
<Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0 0 0 1</DataArray></Points>
<Cells><DataArray type="Int64" Name="connectivity" format="ascii">0 1 2 3</DataArray>
<DataArray type="Int64" Name="offsets" format="ascii">4</DataArray>
<DataArray type="UInt8" Name="types" format="ascii">10</DataArray></Cells>
<PointData><DataArray type="Float64" Name="velocity" NumberOfComponents="3" format="ascii">0 0 1 0 0 2 0 0 3 0 0 4</DataArray></PointData>
<CellData><DataArray type="Float64" Name="von_mises" format="ascii">7.5</DataArray></CellData>
</Piece></UnstructuredGrid></VTKFile>"""
    d = fracdem.read_vtu(write(tmp_path, "t.vtu", text))
    assert d["points"].shape == (4, 3)
    assert d["cells"] == [[0, 1, 2, 3]]
    assert list(d["point_data"]["velocity"][:, 2]) == [1, 2, 3, 4]
    assert d["cell_data"]["von_mises"][0] == 7.5


def test_plots(tmp_path):
    df = pd.DataFrame({"time": [0, 1, 2], "kinetic": [1, 0.5, 0], "strain": [0, 0.5, 1], "total": [1, 1, 1]})
    out = tmp_path / "e.png"
    fig = fracdem.plot_energy(df, out=str(out))
    ax = fig.axes[0]
    assert len(ax.lines) == 3 and ax.get_xlabel() == "time (s)" and ax.get_ylabel() == "energy (J)"
    assert out.stat().st_size > 1000
    log = fracdem.read_log(write(tmp_path, "log", LOG))
    fig = fracdem.plot_thermo(log, ["KinEng", "f_body[1]"], out=str(tmp_path / "t.png"))
    assert len(fig.axes[0].lines) == 2
    with pytest.raises(KeyError):
        fracdem.plot_thermo(log, ["nope"])


def test_cli(tmp_path):
    df = pd.DataFrame({c: [0.0, 1.0, 2.0] for c in fracdem.fem.ENERGY_COLUMNS})
    df.to_csv(tmp_path / "e.csv", index=False)
    env = dict(os.environ, PYTHONPATH=os.path.join(os.path.dirname(__file__), "..", "..", "python"))
    r = subprocess.run([sys.executable, "-m", "fracdem.cli", "energy", str(tmp_path / "e.csv"), "-o",
                        str(tmp_path / "o.png")], env=env, capture_output=True, text=True)
    assert r.returncode == 0 and (tmp_path / "o.png").exists()
    r = subprocess.run([sys.executable, "-m", "fracdem.cli", "energy", str(tmp_path / "missing.csv"), "-o", "x.png"],
                       env=env, capture_output=True, text=True)
    assert r.returncode == 2 and "no such file" in r.stderr


def test_meshgen_volumes_and_roundtrip(tmp_path):
    X, E, G = meshgen.box_tet_mesh(3, 2, 2, 0.3, 0.2, 0.1)
    v = [np.dot(np.cross(X[b] - X[a], X[c] - X[a]), X[d] - X[a]) / 6 for a, b, c, d in E]
    assert min(v) > 0 and abs(sum(v) - 0.3 * 0.2 * 0.1) < 1e-12
    assert len(G["xmin"]) == 2 * 2
    xs = meshgen.graded_axis(0.01, 0.001, 0.1, growth=1.3)
    assert abs(xs[0] + 0.05) < 1e-12 and abs(xs[-1] - 0.05) < 1e-12 and np.all(np.diff(xs) > 0)
    assert abs(np.diff(xs).min() - 0.001) < 1e-12
    path = tmp_path / "m.msh"
    meshgen.write_gmsh22(str(path), X, E, G)
    text = path.read_text()
    assert "$MeshFormat\n2.2 0 8" in text and f"\n{len(X)}\n" in text
