"""fix balance/graph refuses bad input with a clear error naming the command, keyword and what
was expected, refuses fix mesh/surface walls naming the rigid fem/body alternative, and refuses a
second balancer (two would repartition against each other at every check)."""
import os
import re
import tempfile

import harness as h

args = h.parse_args()
STL = """solid plate
 facet normal 0 0 1
  outer loop
   vertex 0 0 0.001
   vertex 0.07 0 0.001
   vertex 0 0.07 0.001
  endloop
 endfacet
endsolid plate
"""
cases = [
    ("fix bal all balance/graph 0 1.1", "Nevery must be a positive integer"),
    ("fix bal all balance/graph 10 0.9", "thresh must be a number >= 1.0"),
    ("fix bal all balance/graph 10 1.1 model magic", "keyword 'model': expected apriori or aposteriori"),
    ("fix bal all balance/graph 10 1.1 cost guess",
     "keyword 'cost': expected counts, calibrated, timed or fitted"),
    ("fix bal all balance/graph 10 1.1 partitioner chaco",
     "keyword 'partitioner': expected metis or scotch or rcb or layers or ptscotch or zoltan-phg "
     "or zoltan-graph"),
    ("fix bal all balance/graph 10 1.1 partitioner layers cells 0",
     "keyword 'partitioner layers' cuts the cell grid by coordinates and needs cells"),
    ("fix bal all balance/graph 10 1.1 partitioner scotch repartition refine",
     "with 'partitioner scotch' each repartition is one SCOTCH_graphRepart call"),
    ("fix bal all balance/graph 10 1.1 partitioner ptscotch cells 2",
     "keyword 'partitioner ptscotch' partitions one vertex per particle"),
    ("fix bal all balance/graph 10 1.1 partitioner ptscotch repartition auto",
     "'partitioner ptscotch' partitions on all ranks in one call"),
    ("fix bal all balance/graph 10 1.1 repartition twice", "keyword 'repartition'"),
    ("fix bal all balance/graph 10 1.1 colour red", "unknown keyword 'colour'"),
    ("fix bal all balance/graph 10 1.1 partioner metis",
     "unknown keyword 'partioner' (expected model, cost, partitioner, repartition, cells, "
     "counts, insert_region or out); did you mean 'partitioner'?"),
    ("fix bal all balance/graph 10 1.1 counts maybe",
     "keyword 'counts': expected pair or recount, got 'maybe'"),
    ("fix bal all balance/graph 10 1.1 cells 0.5", "keyword 'cells'"),
    ("fix bal all balance/graph 10 1.1 model apriori model aposteriori", "keyword 'model' given twice"),
    ("fix bal all balance/graph 10 1.1 insert_region nosuch", "no region 'nosuch'"),
    ("fix bal all balance/graph 10 1.1 model", "keyword 'model' needs a value"),
    ("group lower id <= 10\nfix bal lower balance/graph 10 1.1", "group must be 'all'"),
    ("fix wallmesh all mesh/surface file plate.stl type 1\n"
     "fix bal all balance/graph 10 1.1", "use a rigid 'fix fem/body"),
    ("fix bal all balance/graph 10 1.1\nfix bal2 all balance/graph 20 1.2",
     "fix bal2: fix bal is a balance/graph already and only one may be defined"),
]
for extra, expected in cases:
    wd = tempfile.mkdtemp(prefix="balance_errors_")
    h.copy_inputs(["in.balance_bed"], wd)
    with open(os.path.join(wd, "plate.stl"), "w") as f:
        f.write(STL)
    # The bed script with the balance fix replaced by the line under test, run for one step.
    with open(os.path.join(wd, "in.balance_bed")) as f:
        text = f.read()
    fix_block = re.search(r'if "\$\{balance\} == 1" then &\n  "fix bal all balance/graph[^\n]*\n', text)
    assert fix_block, "in.balance_bed no longer has the balance fix block this test replaces"
    text = text.replace(fix_block.group(0), extra + "\n")
    text = text.replace('if "${balance} == 1" then "variable fbal equal f_bal[2]"', "")
    with open(os.path.join(wd, "in.case"), "w") as f:
        f.write(text)
    out = h.run(args.exe, "in.case", np_=1, workdir=wd, variables=dict(steps=1), expect_fail=True)
    err = [l for l in out.splitlines() if "ERROR" in l]
    h.check(err and expected in err[0], f"'{extra.splitlines()[-1]}' -> {err[0] if err else 'no error'}")
