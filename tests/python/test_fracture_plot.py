"""fracdem.fem.fracture_summary and `fracdem-plot fracture` on a synthetic energy file with a known
load-displacement curve (triangle: peak 10 kN at 2 um)."""
import numpy as np
import pandas as pd
import pytest

from fracdem import cli, fem


def energy_file(path, dissipation="fracture_energy"):
    u = np.linspace(0, 6e-6, 61)
    load = np.where(u <= 2e-6, u / 2e-6 * 1e4, np.maximum(0, 1e4 * (6e-6 - u) / 4e-6))
    df = pd.DataFrame({"step": np.arange(61) * 10, "time": np.arange(61) * 1e-6, "kinetic": 0.0,
                       "strain": 0.0, "external_work": 0.0, "contact_work": 0.0, "total": 0.0,
                       "nodes": 100, "elements": 150, dissipation: np.cumsum(load) * 1e-7,
                       "split_nodes": (u > 4e-6) * 11, "fragments": 1 + (u > 5e-6),
                       "boundary_work": 0.0, "reaction_top_y": -load, "displacement_top_y": u})
    df.to_csv(path, index=False)
    return df


def test_summary_finds_the_peak_and_the_final_state(tmp_path):
    energy_file(tmp_path / "e.csv")
    df = fem.read_energy(tmp_path / "e.csv")
    s = fem.fracture_summary(df, "top", "y")
    assert s["peak_load"] == pytest.approx(1e4, rel=1e-12)
    assert s["displacement_at_peak"] == pytest.approx(2e-6, rel=1e-9)
    assert s["split_nodes"] == 11 and s["fragments"] == 2
    assert s["dissipation_column"] == "fracture_energy"
    assert s["dissipated"] == pytest.approx(df["fracture_energy"].iloc[-1])


def test_summary_of_a_plastic_body_reads_its_plastic_work(tmp_path):
    # A plastic body's energy file names its dissipation plastic_work (fix fem/body docs).
    energy_file(tmp_path / "p.csv", dissipation="plastic_work")
    df = fem.read_energy(tmp_path / "p.csv")
    s = fem.fracture_summary(df, "top", "y")
    assert s["dissipation_column"] == "plastic_work"
    assert s["dissipated"] == pytest.approx(df["plastic_work"].iloc[-1])
    df.drop(columns=["plastic_work"]).to_csv(tmp_path / "n.csv", index=False)
    with pytest.raises(KeyError, match="dissipation columns"):
        fem.fracture_summary(fem.read_energy(tmp_path / "n.csv"), "top", "y")


def test_cli_writes_both_plots_and_names_the_groups_on_error(tmp_path, capsys):
    energy_file(tmp_path / "e.csv")
    assert cli.main(["fracture", str(tmp_path / "e.csv"), "--group", "top", "--component", "y",
                     "-o", str(tmp_path / "f")]) == 0
    assert (tmp_path / "f_load.png").stat().st_size > 1000
    assert (tmp_path / "f_energy.png").stat().st_size > 1000
    assert cli.main(["fracture", str(tmp_path / "e.csv"), "--group", "bottom", "-o", str(tmp_path / "g")]) == 2
    assert "groups: ['top']" in capsys.readouterr().err
