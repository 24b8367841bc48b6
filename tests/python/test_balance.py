"""Tests of fracdem.balance: run statistics from LIGGGHTS/LAMMPS logs, balance CSV summaries, plots."""
import numpy as np
import pandas as pd

from fracdem import balance

LIGGGHTS_TAIL = """Loop time of 3.5 on 4 procs for 4000 steps with 5346 atoms, finish time Mon Nov 23 2026

Nlocal:    1336.5 ave 1400 max 1300 min
Histogram: 1 0 0 0 0 0 0 0 0 3
Nghost:    1004 ave 1388 max 700 min
Neighs:    4154.5 ave 4412 max 3822 min
"""

LAMMPS_TAIL = """Loop time of 1.41775 on 4 procs for 4000 steps with 5346 atoms
MPI task timing breakdown:
Section |  min time  |  avg time  |  max time  |%varavg| %total
---------------------------------------------------------------
Pair    | 0.1678     | 0.16896    | 0.17052    |   0.3 | 11.92
Neigh   | 0.030558   | 0.030745   | 0.030941   |   0.1 |  2.17
Other   |            | 0.08217    |            |       | 21.35
Nlocal:        1336.50 ave        1337 max        1336 min
Nghost:        894.750 ave         901 max         887 min
Neighs:        4320.75 ave        4361 max        4245 min
"""


def test_run_stats_liggghts():
    s = balance.run_stats("Loop time of 9 on 4 procs for 1 steps\n" + LIGGGHTS_TAIL)
    assert s["loop_s"] == 3.5 and s["nprocs"] == 4  # the last run wins
    assert (s["nghost_ave"], s["nghost_max"], s["nghost_min"]) == (1004, 1388, 700)
    assert s["neighs_max"] / s["neighs_ave"] == 4412 / 4154.5


def test_run_stats_lammps_breakdown():
    s = balance.run_stats(LAMMPS_TAIL)
    assert s["pair_max_s"] == 0.17052 and s["pair_avg_s"] == 0.16896
    assert s["neigh_min_s"] == 0.030558
    assert "other_avg_s" not in s  # the Other row has no min/max: skipped, not misread
    assert s["nghost_ave"] == 894.75


def make_csv(nprocs=2):
    # Two intervals: rank work (4, 0) then (2, 2): B = 2 then 1; work-model speedup = 8/6.
    work = [[4.0, 0.0], [2.0, 2.0]]
    rows = []
    for k, w in enumerate(work):
        avg = sum(w) / nprocs
        rows.append(dict(step=100 * (k + 1), imbalance=[2.0, 1.0][k], repartitioned=[1, 0][k],
                         predicted_imbalance=1.01, migrated=[10, 0][k], partition_seconds=[0.5, 0][k],
                         migration_seconds_total=0.25, ghost_max_over_avg=1.0, ghosts_total=[40, 60][k],
                         edge_cut=3, natoms=100, work_max=max(w), work_avg=avg,
                         measured_imbalance=max(w) / avg, cpu_work_max=max(w), cpu_work_avg=avg,
                         **{f"cpu_rank{r}": w[r] for r in range(nprocs)}))
    return pd.DataFrame(rows)


def test_summarize_balance_analytic():
    s = balance.summarize_balance(make_csv(), nprocs=2, loop_s=10.0)
    assert np.isclose(s["measured_B"], 1.5)
    assert np.isclose(s["speedup"], (2 + 2) * 2 / (4 + 2))
    assert s["repartitions"] == 1 and s["migrated"] == 10
    assert np.isclose(s["ghosts_per_rank"], 25.0)
    assert np.isclose(s["partition_share"], 0.075)
    assert s["work_per_rank"] == [6.0, 2.0]


def test_markdown_table_and_plots(tmp_path):
    t = balance.markdown_table([dict(a="x", b=1.23456), dict(a="y")], ["a", "b"])
    assert t.splitlines()[2] == "| x | 1.23 |" and t.splitlines()[3] == "| y |  |"
    out = tmp_path / "w.png"
    balance.plot_rank_work({"m1": [1, 2], "m2": [1.5, 1.5]}, out=str(out))
    assert out.stat().st_size > 1000
    out2 = tmp_path / "h.png"
    balance.plot_imbalance_history({"m1": ([1, 2], [2.0, 1.0])}, out=str(out2))
    assert out2.stat().st_size > 1000


def test_cli_balance(tmp_path):
    from fracdem import cli

    csv = tmp_path / "balance.csv"
    make_csv().to_csv(csv, index=False)
    assert cli.main(["balance", str(csv), "-o", str(tmp_path / "b")]) == 0
    assert (tmp_path / "b_history.png").stat().st_size > 1000
    assert (tmp_path / "b_rank_work.png").stat().st_size > 1000
