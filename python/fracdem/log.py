"""Parser for LIGGGHTS/LAMMPS log files: thermo blocks, loop times, warnings and errors."""
import re
from dataclasses import dataclass, field

import pandas as pd


class LogError(RuntimeError):
    """An ERROR line was found in a log read with check_errors=True."""


@dataclass
class Log:
    """Parsed log: one DataFrame per run, plus timing and messages."""

    runs: list = field(default_factory=list)
    loop_times: list = field(default_factory=list)
    nprocs: int = None
    errors: list = field(default_factory=list)
    warnings: list = field(default_factory=list)

    @property
    def thermo(self):
        """All runs concatenated; a step repeated at a run boundary keeps the later row."""
        if not self.runs:
            return pd.DataFrame()
        df = pd.concat(self.runs, ignore_index=True)
        if "Step" in df:
            df = df.drop_duplicates(subset="Step", keep="last").reset_index(drop=True)
        return df


_LOOP = re.compile(r"^Loop time of\s+(\S+)\s+on\s+(\d+)\s+procs")


def read_log(path, check_errors=False):
    """Read a log file (log.liggghts or captured stdout) into a Log."""
    log = Log()
    header, rows = None, []

    def close():
        if header is not None:
            log.runs.append(pd.DataFrame(rows, columns=header))

    with open(path, errors="replace") as f:
        for line in f:
            words = line.split()
            if line.startswith("ERROR"):
                log.errors.append(line.strip())
            elif line.startswith("WARNING"):
                log.warnings.append(line.strip())
            m = _LOOP.match(line)
            if m:
                log.loop_times.append(float(m.group(1)))
                log.nprocs = int(m.group(2))
                close()
                header, rows = None, []
                continue
            if words and words[0] == "Step":
                close()
                header, rows = words, []
                continue
            if header is not None and len(words) == len(header):
                try:
                    rows.append([float(w) for w in words])
                except ValueError:
                    pass
    close()
    if check_errors and log.errors:
        raise LogError(log.errors[0])
    return log
