"""Plots of fracdem runs: body energy histories and thermo columns."""
import matplotlib

import pandas as pd


def _pyplot(save):
    if save:
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def new_figure(save, figsize=(6, 3.5)):
    """(pyplot, figure, axes) for one plot; a headless backend when the plot is only saved."""
    plt = _pyplot(save)
    fig, ax = plt.subplots(figsize=figsize)
    return plt, fig, ax


def finish_figure(fig, ax, out=None, title=None, close=False):
    """Legend, title and layout; saved to `out` if given; closed if asked. Returns the figure."""
    if title:
        ax.set_title(title)
    ax.legend()
    fig.tight_layout()
    if out:
        fig.savefig(out, dpi=120)
    if close:
        import matplotlib.pyplot as plt

        plt.close(fig)
    return fig


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
    return finish_figure(fig, ax, out)


def plot_thermo(log, columns, out=None):
    """Plot thermo columns of a Log (or DataFrame) against Step, one line each."""
    _, fig, ax = new_figure(out is not None)
    df = log if isinstance(log, pd.DataFrame) else log.thermo
    for c in columns:
        if c not in df:
            raise KeyError(f"thermo has no column {c!r}; it has {list(df.columns)}")
        ax.plot(df["Step"], df[c], label=c)
    ax.set_xlabel("step")
    return finish_figure(fig, ax, out)


def plot_fracture(df, group, component="x", out_prefix=None):
    """Load-displacement curve of a group (|reaction| against its mean displacement) and the energy
    history (kinetic, strain, fracture, boundary work) of a fracturing fem/body run."""
    save = out_prefix is not None
    _, fig1, ax1 = new_figure(save)
    u, r = df[f"displacement_{group}_{component}"], df[f"reaction_{group}_{component}"].abs()
    ax1.plot(u, r, label=f"{group} ({component})")
    ax1.set_xlabel("displacement (m)")
    ax1.set_ylabel("load (N)")
    finish_figure(fig1, ax1, out=save and f"{out_prefix}_load.png", close=save)
    _, fig2, ax2 = new_figure(save)
    for c in ("kinetic", "strain", "fracture_energy", "plastic_work", "viscous_work", "boundary_work"):
        if c in df:
            ax2.plot(df["time"], df[c], label=c)
    ax2.set_xlabel("time (s)")
    ax2.set_ylabel("energy (J)")
    finish_figure(fig2, ax2, out=save and f"{out_prefix}_energy.png", close=save)
    return fig1, fig2
