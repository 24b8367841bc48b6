"""fracdem: read LIGGGHTS/fracdem logs and body outputs, plot energy histories, generate meshes."""
from .fem import read_energy, read_pvd, read_vtu
from .log import Log, LogError, read_log
from .plots import plot_energy, plot_thermo

__version__ = "0.1.0"
__all__ = ["Log", "LogError", "read_log", "read_energy", "read_pvd", "read_vtu", "plot_energy", "plot_thermo"]
