// The fracture check as a plan made on a const body (fracture_rules.h decides) and its application.
#include "fracture/fracture_plan.h"

#include <algorithm>
#include <optional>

#include "fracture/fracture_rules.h"

namespace fracdem
{
using namespace fracture_rules;

CrackNodes whole_crack_nodes(const Body& whole, double min_size)
{
  CrackNodes c;
  c.split = split_nodes(whole);
  c.whole_star.assign(whole.num_nodes(), 1);
  c.on_crack = c.split;
  if (min_size > 0)
    for (size_t k = 0; k < whole.cut_nodes().size(); k += 3)
      c.on_crack[whole.cut_nodes()[k]] = 1;
  return c;
}

namespace
{

// Applies one step to body; what it did goes to out.
void apply_step(Body& body, const FractureStep& step, bool remove_mass, FractureOutcome& out)
{
  switch (step.kind) {
  case FractureStep::Kind::Cut: {
    const ElementCut& c = step.cut;
    CutEvent ev{step.node, c.elem, c.u, c.w, c.t, -1, {}};
    std::vector<int> added;
    ev.new_node = body.bisect_edge(c.u, c.w, c.t, &added, c.joins);
    for (int e : added) // the cut element's child first, then the neighbours'
      if (body.element_parent(e) == c.elem) ev.new_elems.push_back(e);
    for (int e : added)
      if (body.element_parent(e) != c.elem) ev.new_elems.push_back(e);
    out.cuts.push_back(ev);
    return;
  }
  case FractureStep::Kind::Split:
  case FractureStep::Kind::Part: {
    SplitEvent ev{step.node, -1, {step.normal[0], step.normal[1], step.normal[2]},
                  static_cast<int>(step.sides.side_b.size())};
    ev.copy = body.split_node(step.sides);
    out.splits.push_back(ev);
    return;
  }
  case FractureStep::Kind::Erode:
    body.erode(step.elements, remove_mass);
    out.eroded.insert(out.eroded.end(), step.elements.begin(), step.elements.end());
    return;
  case FractureStep::Kind::Undecided:
    return;
  }
}

// Makes a plan: every decision reads view(), the body as the steps taken so far left it. The
// first step copies the body once (a check that changes nothing copies nothing); a part's plan
// (a forecast) stops at its first step and copies nothing at all.
class Planner
{
public:
  Planner(const Body& body, const FracturePlanInput& in, FracturePlan& plan)
      : body_(body), in_(in), plan_(plan)
  {
    plan_.remove_mass = in.rule.remove_mass;
  }
  const Body& view() const { return scratch_ ? *scratch_ : body_; }
  bool done() const { return in_.part && !plan_.steps.empty(); }
  void take(FractureStep step)
  {
    plan_.steps.push_back(std::move(step));
    if (in_.part) return;
    if (!scratch_) scratch_.emplace(body_);
    FractureOutcome ignored;
    apply_step(*scratch_, plan_.steps.back(), in_.rule.remove_mass, ignored);
  }
  const FracturePlan& plan() const { return plan_; }
  double fraction(int e) const { return in_.fraction ? in_.fraction(e) : view().piece_fraction(e); }

private:
  const Body& body_;
  const FracturePlanInput& in_;
  FracturePlan& plan_;
  std::optional<Body> scratch_;
};

// Cuts through the elements of v's star that the failure plane crosses (each adds a node on the
// crack's line). A cut puts a face in the plane and competes with every later one: a handful per
// point at most; the bound only guards the loop.
void plan_cuts(Planner& p, int v, const double n[3], double min_size, std::vector<char>& on_crack)
{
  constexpr int kMaxCutsPerPoint = 8;
  for (int k = 0; k < kMaxCutsPerPoint && !p.done(); ++k) {
    const Body& body = p.view();
    FractureStep step;
    step.kind = FractureStep::Kind::Cut;
    step.node = v;
    step.cut = find_element_cut(body.mesh(), body.stars(), body.positions().data(), v, n,
                                min_size, [&p](int e) { return p.fraction(e); });
    if (!step.cut.found() || cut_splits_failed_quad(body, step.cut)) return;
    p.take(std::move(step));
    on_crack.push_back(1);
  }
}

// Crack point v: cuts (min_size), then the split along its failure plane, unless the band is
// already cracked, the opening carries tension or the split cuts loose a chip.
void plan_point(Planner& p, const FracturePlanInput& in, int v, std::vector<char>& on_crack)
{
  const bool cutting = in.rule.min_size > 0;
  // A cut crack runs exactly along its plane, so only nodes much nearer to it than a third of
  // an element (those the min_size guard kept the cut from passing beside) continue it.
  const double line_tolerance = cutting ? std::min(1.0 / 3.0, 0.5 * in.rule.min_size) : 1.0 / 3.0;
  double n[3] = {0, 0, 0};
  const int e = driving_element(p.view(), v, n);
  if (e < 0 || band_already_cracked(p.view(), on_crack, e, v, n, line_tolerance)) return;
  // With cuts the tension check comes before them (they change the star), on the plan of the
  // star as it is; the split then opens along the cut.
  if (cutting) {
    if (opening_carries_tension(p.view(), p.view().plan_split(v, n), n)) return;
    plan_cuts(p, v, n, in.rule.min_size, on_crack);
    if (p.done()) return;
  }
  const Body& body = p.view();
  FractureStep step;
  step.kind = FractureStep::Kind::Split;
  step.node = v;
  std::copy(n, n + 3, step.normal);
  step.sides = body.plan_split(v, n);
  if (!step.sides.splittable() || (!cutting && opening_carries_tension(body, step.sides, n)))
    return;
  if (cuts_loose_chip(body, step.sides, in.part ? &in.part->whole_star : nullptr)) return;
  p.take(std::move(step));
  on_crack[v] = 1;
  on_crack.push_back(1);
}

// Parts node w into one node per class of its star's elements; the class with most elements
// (lowest among equals) keeps w.
void plan_parting(Planner& p, int w, const std::function<int(int)>& class_of)
{
  std::map<int, int> size;
  for (const int* e = p.view().stars().begin(w); e != p.view().stars().end(w); ++e)
    ++size[class_of(*e)];
  if (size.size() < 2) return;
  int keep = size.begin()->first;
  for (const auto& c : size)
    if (c.second > size[keep]) keep = c.first;
  for (const auto& c : size) {
    if (c.first == keep) continue;
    FractureStep step;
    step.kind = FractureStep::Kind::Part;
    step.node = step.sides.node = w;
    const NodeStars& stars = p.view().stars();
    for (const int* e = stars.begin(w); e != stars.end(w); ++e)
      (class_of(*e) == c.first ? step.sides.side_b : step.sides.side_a).push_back(*e);
    p.take(std::move(step));
  }
}

// Fragments are never held together by a single node whose star fell into pieces that touch
// only at it, once it is split (a split node or its copy: cracks on several sides of it): it is
// parted into one node per face-connected piece at once, but debris stays with the group that
// owns it (no chip is cut loose). The nodes that still join groups (never split: a surface node
// at a crack's mouth, one between two cracks) are joints without material area: the joints
// between two groups go together, as the last bond between them, where neither is a chip, once
// they pull the groups apart with more than the unfailed material across them could carry.
// Parting a node cuts no facet, so the pieces and groups stay those of the start of the pass.
void plan_separation(Planner& p, FacePieces& pieces)
{
  const std::vector<int> candidates = pinch_candidates(p.view());
  if (candidates.empty()) return; // no crack: no piece touches another at a node only
  std::vector<char> split_now(p.view().num_nodes(), 0), whole; // by this plan's crack splits
  for (const FractureStep& step : p.plan().steps)
    if (step.kind == FractureStep::Kind::Split) split_now[step.node] = 1;
  const FacePieces& fp = face_pieces(p.view(), pieces);
  const std::vector<int> piece = fp.piece;
  const std::vector<int> group = pinch_groups(p.view(), fp, whole);
  const int first_copy = p.view().num_nodes();
  for (int v : candidates)
    if (p.view().parents()[v] >= 0 || split_now[v]) {
      const std::map<int, int> cls = star_classes(p.view(), v, piece, group, whole);
      plan_parting(p, v, [&](int e) { return cls.at(e); });
    }
  const Joints joints = group_joints(p.view(), fp, group);
  const std::set<std::pair<int, int>> parting = parting_pairs(p.view(), group, whole, joints);
  std::set<int> nodes;
  for (const auto& pair : parting)
    nodes.insert(joints.at(pair).begin(), joints.at(pair).end());
  for (int w : nodes) {
    const std::map<int, int> cls = joined_classes(p.view(), w, group, parting);
    plan_parting(p, w, [&](int e) { return cls.at(group[e]); });
  }
  keep_pieces_after_parting(p.view(), first_copy, pieces);
}

// A failed element (no tension left) squeezed below the host step would collapse the stable step
// of the whole body; with erode_cracked, every failed element a crack has reached goes.
void plan_erosion(Planner& p, const FracturePlanInput& in)
{
  const Body& body = p.view();
  const Mesh& mesh = body.mesh();
  std::vector<char> split;
  if (in.rule.erode_cracked) split = in.part ? in.part->split : split_nodes(body);
  FractureStep step;
  step.kind = FractureStep::Kind::Erode;
  for (int e : in.failed) {
    if (!mesh.active[e]) continue;
    bool erodes = false;
    if (in.rule.erode_cracked) {
      for (int a = 0; a < nodes_per_elem(mesh.etype[e]) && !erodes; ++a)
        erodes = split[mesh.conn[e][a]] != 0;
    } else {
      erodes = body.element_time_step(e) < in.rule.dt;
    }
    if (erodes) step.elements.push_back(e);
  }
  if (!step.elements.empty()) p.take(std::move(step));
}

} // namespace

FracturePlan plan_fracture(const Body& body, const FracturePlanInput& in)
{
  FracturePlan plan;
  Planner p(body, in, plan);
  std::vector<char> on_crack =
      in.part ? in.part->on_crack : whole_crack_nodes(body, in.rule.min_size).on_crack;
  for (int v : in.points) {
    if (in.part && !in.part->whole_star[v]) {
      FractureStep step;
      step.node = v; // Undecided
      p.take(std::move(step));
    } else {
      plan_point(p, in, v, on_crack);
    }
    if (p.done()) return plan;
  }
  FacePieces taken;
  FacePieces& pieces = in.pieces ? *in.pieces : taken;
  if (!in.part) plan_separation(p, pieces);
  if (in.rule.erode) plan_erosion(p, in);
  if (in.outlook) {
    plan.outlook.pinch_left = pinch_may_separate(p.view(), pieces);
    plan.outlook.pieces_touch = pieces_touch_at_nodes(p.view(), pieces);
  }
  return plan;
}

FractureOutcome apply_fracture_plan(Body& body, const FracturePlan& plan)
{
  FractureOutcome out;
  for (const FractureStep& step : plan.steps)
    apply_step(body, step, plan.remove_mass, out);
  return out;
}

std::vector<SplitEvent> insert_cracks(Body& body, const std::vector<int>& points, double min_size,
                                      std::vector<CutEvent>* cuts, FacePieces* pieces)
{
  FracturePlanInput in;
  in.points = points;
  in.rule.min_size = min_size;
  in.rule.erode = false;
  in.pieces = pieces;
  FractureOutcome out = apply_fracture_plan(body, plan_fracture(body, in));
  if (cuts) cuts->insert(cuts->end(), out.cuts.begin(), out.cuts.end());
  return out.splits;
}

} // namespace fracdem
