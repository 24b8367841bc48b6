"""After read_restart, a fix fem/body that would silently not continue the stored body is refused:
re-issued under another fix ID (the host matches restart states by ID, so it would start afresh
from its mesh), or with other placement keywords ('move', 'rigid') than the stored state keeps.
The same command continues, and 'run 0' before a new body drops the stored state on purpose."""
import os
import tempfile

import harness as h

args = h.parse_args()
BODY = "fix {id} all fem/body file bar.msh type 2 {rest}"
SAME = "density 2000 youngs 1e8 poisson 0.3 move 0 0 0.01 fixed xmin"
cases = [  # (body line, body ID, expected error or None)
    (BODY.format(id="body", rest=SAME), "body", None),
    ("run 0\n" + BODY.format(id="slab", rest=SAME), "slab", None),
    (BODY.format(id="slab", rest=SAME), "slab",
     "fix fem/body slab: the restart file holds the state of fix fem/body 'body', which no fix"),
    (BODY.format(id="body", rest=SAME.replace("0.01", "0.02")), "body",
     "restart file holds this body with 'rigid no move 0 0 0.01' but this command gives "
     "'rigid no move 0 0 0.02'"),
    (BODY.format(id="body", rest="rigid yes move 0 0 0.01"), "body",
     "restart file holds this body with 'rigid no move 0 0 0.01' but this command gives "
     "'rigid yes move 0 0 0.01'"),
]
wd = tempfile.mkdtemp(prefix="restart_mismatch_")
h.make_box_mesh(os.path.join(wd, "bar.msh"), (6, 2, 2), (0.3, 0.05, 0.05), (0, -0.025, -0.025))
h.copy_inputs(["in.restart_placement_a", "in.restart_placement_b", "in.fe_common"], wd)
h.run(args.exe, "in.restart_placement_a", workdir=wd)
with open(os.path.join(wd, "in.restart_placement_b")) as f:
    template = f.read()
for line, body_id, expected in cases:
    with open(os.path.join(wd, "in.case"), "w") as f:
        f.write(template.replace("BODYLINE", line).replace("BODYID", body_id))
    label = line.replace("\n", "; ")[:100]
    if expected is None:
        out = h.run(args.exe, "in.case", workdir=wd)
        h.check(h.thermo_blocks(out)[-1][1], f"'{label}' runs")
        continue
    out = h.run(args.exe, "in.case", workdir=wd, expect_fail=True)
    err = [l for l in out.splitlines() if "ERROR" in l]
    h.check(bool(err) and expected in err[0], f"'{label}' -> {err[0] if err else 'no ERROR line'}")
