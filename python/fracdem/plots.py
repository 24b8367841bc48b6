"""Plots of fracdem runs: body energy histories and thermo columns."""
import matplotlib

import pandas as pd


def _pyplot(save):
    if save:
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plot_energy(data, columns=None, ax=None, out=None):
    """Plot energy columns (default kinetic, strain, total) of a fem/body energy DataFrame vs time."""
    plt = _pyplot(out is not None)
    df = data if isinstance(data, pd.DataFrame) else data.thermo
    columns = columns or [c for c in ("kinetic", "strain", "total") if c in df]
    x = "time" if "time" in df else "Step"
    fig = ax.figure if ax is not None else plt.figure(figsize=(6, 3.5))
    ax = ax or fig.add_subplot(111)
    for c in columns:
        ax.plot(df[x], df[c], label=c)
    ax.set_xlabel("time (s)" if x == "time" else "step")
    ax.set_ylabel("energy (J)")
    ax.legend()
    fig.tight_layout()
    if out:
        fig.savefig(out, dpi=120)
    return fig


def plot_thermo(log, columns, out=None):
    """Plot thermo columns of a Log (or DataFrame) against Step, one line each."""
    plt = _pyplot(out is not None)
    df = log if isinstance(log, pd.DataFrame) else log.thermo
    fig, ax = plt.subplots(figsize=(6, 3.5))
    for c in columns:
        if c not in df:
            raise KeyError(f"thermo has no column {c!r}; it has {list(df.columns)}")
        ax.plot(df["Step"], df[c], label=c)
    ax.set_xlabel("step")
    ax.legend()
    fig.tight_layout()
    if out:
        fig.savefig(out, dpi=120)
    return fig
