// Restart records of distributed bodies (see part_restart.h).
#include "body/part_restart.h"

#include "fem/node_split.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace fracdem
{

namespace
{

constexpr int kAccounts = 6; // Body::Accounts as doubles

void put_accounts(const Body::Accounts& a, std::vector<double>& buf)
{
  buf.insert(buf.end(), {a.time, a.external, a.contact, a.boundary, a.shield_work, a.shield_hits});
}

Body::Accounts get_accounts(const double* p)
{
  Body::Accounts a;
  a.time = p[0];
  a.external = p[1];
  a.contact = p[2];
  a.boundary = p[3];
  a.shield_work = p[4];
  a.shield_hits = p[5];
  return a;
}

int global_node(const MeshPart* part, int n)
{
  return part ? part->global_node[n] : n;
}
int global_elem(const MeshPart* part, int e)
{
  return part ? part->global_elem[e] : e;
}

// The accounts this body starts from: all of them, or the clock alone.
Body::Accounts share_of(const Body::Accounts& total, bool take_accounts)
{
  if (take_accounts) return total;
  Body::Accounts a;
  a.time = total.time;
  return a;
}

[[noreturn]] void mismatch(const std::string& what)
{
  throw std::runtime_error("restart file holds a distributed body " + what);
}

} // namespace

void unpack_parts_record(const double* record, Body& body, const MeshPart* part, bool take_accounts)
{
  const int global_nodes = static_cast<int>(record[1]), global_elems = static_cast<int>(record[2]);
  const int nn = body.num_nodes(), ne = body.mesh().num_elems();
  for (int n = 0; n < nn; ++n)
    if (global_node(part, n) >= global_nodes)
      mismatch("of " + std::to_string(global_nodes) + " nodes, but this mesh has more");
  if (!part && (nn != global_nodes || ne != global_elems))
    mismatch("of " + std::to_string(global_nodes) + " nodes / " + std::to_string(global_elems) +
             " elements, but the mesh has " + std::to_string(nn) + " / " + std::to_string(ne));
  const double* motion = record + 3 + kAccounts;
  // Where each element's values start (sizes vary with the element type).
  std::vector<const double*> elem(global_elems);
  const double* p = motion + 6 * static_cast<size_t>(global_nodes);
  for (int g = 0; g < global_elems; ++g) {
    elem[g] = p;
    p += 1 + static_cast<int>(p[0]);
  }
  for (int n = 0; n < nn; ++n)
    body.set_node_motion(n, motion + 6 * static_cast<size_t>(global_node(part, n)));
  for (int e = 0; e < ne; ++e) {
    const int g = global_elem(part, e);
    if (g >= global_elems) mismatch("with fewer elements than this mesh");
    if (static_cast<int>(elem[g][0]) != body.element_record_size(e))
      mismatch("whose element " + std::to_string(g) + " has " +
               std::to_string(static_cast<int>(elem[g][0])) +
               " history values, but this body's "
               "has " +
               std::to_string(body.element_record_size(e)) +
               "; use the same 'material' and 'bulk_viscosity'");
    body.unpack_element(e, elem[g] + 1);
  }
  body.set_accounts(share_of(get_accounts(record + 3), take_accounts));
}

void copy_whole_into_part(const Body& whole, Body& body, const MeshPart& part, bool take_accounts)
{
  const int mesh_nodes = whole.num_nodes();
  for (int g = 0; g < mesh_nodes; ++g)
    if (whole.parents()[g] >= 0)
      throw std::runtime_error("restart file holds a cracked body; 'parallel distributed' bodies "
                               "cannot hold split nodes: use 'parallel replicated'");
  if (whole.eroded().elements > 0)
    throw std::runtime_error("restart file holds a body with eroded elements; 'parallel "
                             "distributed' bodies cannot hold them: use 'parallel replicated'");
  const std::vector<double>& x = whole.positions();
  const std::vector<double>& v = whole.velocities();
  for (int n = 0; n < body.num_nodes(); ++n) {
    const int g = part.global_node[n];
    const double xv[6] = {x[3 * g], x[3 * g + 1], x[3 * g + 2],
                          v[3 * g], v[3 * g + 1], v[3 * g + 2]};
    body.set_node_motion(n, xv);
  }
  std::vector<double> values;
  for (int e = 0; e < body.mesh().num_elems(); ++e) {
    const int g = part.global_elem[e];
    values.resize(whole.element_record_size(g));
    whole.pack_element(g, values.data());
    body.unpack_element(e, values.data());
  }
  body.set_accounts(share_of(whole.accounts(), take_accounts));
}

/* ----------------------------------------------------------------------
   a distributed body that breaks: gather whole, scatter in new parts
------------------------------------------------------------------------- */

namespace
{

constexpr int kOutputs = 4 + 6; // strain energy, contact force total (3), erosion account (6)

void put_outputs(const Body::Outputs& o, std::vector<double>& buf)
{
  buf.insert(buf.end(),
             {o.strain_energy, o.contact_force_total[0], o.contact_force_total[1],
              o.contact_force_total[2], double(o.eroded.elements), o.eroded.mass, o.eroded.energy,
              o.eroded.momentum[0], o.eroded.momentum[1], o.eroded.momentum[2]});
  buf.push_back(static_cast<double>(o.reactions.size()));
  buf.insert(buf.end(), o.reactions.begin(), o.reactions.end());
}

// Reads put_outputs at p, adding to o (o.reactions sized on first use); returns the end.
const double* add_outputs(const double* p, Body::Outputs& o)
{
  o.strain_energy += p[0];
  for (int d = 0; d < 3; ++d)
    o.contact_force_total[d] += p[1 + d];
  o.eroded.elements += static_cast<int>(p[4]);
  o.eroded.mass += p[5];
  o.eroded.energy += p[6];
  for (int d = 0; d < 3; ++d)
    o.eroded.momentum[d] += p[7 + d];
  const int nr = static_cast<int>(p[kOutputs]);
  o.reactions.resize(nr, 0.0);
  for (int k = 0; k < nr; ++k)
    o.reactions[k] += p[kOutputs + 1 + k];
  return p + kOutputs + 1 + nr;
}

} // namespace

void PartTopology::reset(int nodes, int elems)
{
  node_parent.assign(nodes, -1);
  cut_u.assign(nodes, -1);
  cut_w.assign(nodes, -1);
  elem_parent.assign(elems, -1);
  node_split.clear();
  elem_root.clear();
  elem_fragment.clear();
  cut = false;
}

PartTopology whole_topology(const Body& whole)
{
  PartTopology t;
  t.reset(whole.num_nodes(), whole.mesh().num_elems());
  t.node_parent = whole.parents();
  const std::vector<int>& cuts = whole.cut_nodes();
  for (size_t k = 0; k + 2 < cuts.size(); k += 3) {
    t.cut_u[cuts[k]] = cuts[k + 1];
    t.cut_w[cuts[k]] = cuts[k + 2];
  }
  const int ne = whole.mesh().num_elems();
  t.elem_root.resize(ne);
  for (int e = 0; e < ne; ++e) {
    t.elem_parent[e] = whole.element_parent(e);
    int r = e;
    while (whole.element_parent(r) >= 0)
      r = whole.element_parent(r);
    t.elem_root[e] = r;
  }
  t.node_split.assign(whole.num_nodes(), 0);
  for (int n = 0; n < whole.num_nodes(); ++n)
    if (t.node_parent[n] >= 0) t.node_split[n] = t.node_split[t.node_parent[n]] = 1;
  element_components(whole.mesh(), t.elem_fragment);
  t.cut = ne > whole.mesh_elements();
  return t;
}

CrackNodes part_crack_nodes(const MeshPart& part, const PartTopology& topo, double min_size)
{
  const int nn = part.num_nodes();
  CrackNodes c;
  c.split.assign(nn, 0);
  c.on_crack.assign(nn, 0);
  c.whole_star.assign(nn, 1);
  const bool known = static_cast<int>(topo.node_split.size()) == nn;
  bool cracked = false;
  for (int n = 0; n < nn; ++n) {
    const bool cut = static_cast<int>(topo.cut_u.size()) == nn && topo.cut_u[n] >= 0;
    const bool copy = static_cast<int>(topo.node_parent.size()) == nn && topo.node_parent[n] >= 0;
    cracked |= cut || copy;
    c.split[n] = known && topo.node_split[n] != 0;
    c.on_crack[n] = c.split[n] || (min_size > 0 && cut);
    c.whole_star[n] = !part.shared(n);
  }
  if (cracked && !known) c.whole_star.assign(nn, 0);
  return c;
}

std::vector<double> pack_part_whole(const Body& body, const MeshPart& part,
                                    const PartTopology& topo)
{
  const Mesh& mesh = body.mesh();
  const int nn = body.num_nodes(), ne = mesh.num_elems();
  int owned = 0;
  for (int n = 0; n < nn; ++n)
    owned += body.counted(n) ? 1 : 0;
  std::vector<double> buf = {double(part.part), double(owned), double(ne)};
  put_accounts(body.accounts(), buf);
  put_outputs(body.outputs(), buf);
  const std::vector<int>* failed = body.failed_elements();
  buf.push_back(body.damaged_points());
  buf.push_back(failed ? static_cast<double>(failed->size()) : 0.0);
  if (failed)
    for (int e : *failed)
      buf.push_back(part.global_elem[e]);
  for (int n = 0; n < nn; ++n) {
    if (!body.counted(n)) continue; // its owner sends it
    buf.push_back(part.global_node[n]);
    buf.resize(buf.size() + Body::kNodeRecordSize);
    body.pack_node(n, buf.data() + buf.size() - Body::kNodeRecordSize);
    buf.insert(buf.end(),
               {double(topo.node_parent[n]), double(topo.cut_u[n]), double(topo.cut_w[n])});
  }
  for (int e = 0; e < ne; ++e) {
    buf.insert(buf.end(), {double(part.global_elem[e]), double(mesh.active[e])});
    for (int a = 0; a < 4; ++a)
      buf.push_back(mesh.conn[e][a] >= 0 ? part.global_node[mesh.conn[e][a]] : -1.0);
    buf.push_back(topo.elem_parent[e]);
    const int size = body.element_record_size(e);
    buf.push_back(size);
    buf.resize(buf.size() + size);
    body.pack_element(e, buf.data() + buf.size() - size);
  }
  return buf;
}

namespace
{

// The gathered nodes and elements, by global number.
struct GatheredParts {
  std::vector<double> node;                   // kNodeRecordSize per node
  std::vector<int> parent, cut_u, cut_w;      // per node
  std::vector<int> active, conn, elem_parent; // per element (conn: 4)
  std::vector<std::vector<double>> values;    // per element: pack_element
  Body::Accounts accounts;
};

const double* read_part(const double* p, GatheredParts& g, GatheredBody& out, bool first)
{
  const int part = static_cast<int>(p[0]), owned = static_cast<int>(p[1]);
  const int ne = static_cast<int>(p[2]);
  const Body::Accounts a = get_accounts(p + 3);
  if (first) g.accounts.time = a.time; // the clock is every part's
  g.accounts.external += a.external;
  g.accounts.contact += a.contact;
  g.accounts.boundary += a.boundary;
  g.accounts.shield_work += a.shield_work;
  g.accounts.shield_hits += a.shield_hits;
  p = add_outputs(p + 3 + kAccounts, out.outputs);
  out.damaged += static_cast<int>(p[0]);
  const int nf = static_cast<int>(p[1]);
  out.failed.insert(out.failed.end(), p + 2, p + 2 + nf);
  p += 2 + nf;
  const int nnodes = static_cast<int>(g.parent.size()), nelems = static_cast<int>(g.active.size());
  for (int i = 0; i < owned; ++i) {
    const int n = static_cast<int>(p[0]);
    if (n < 0 || n >= nnodes) mismatch("node index out of range");
    std::copy(p + 1, p + 1 + Body::kNodeRecordSize, &g.node[Body::kNodeRecordSize * size_t(n)]);
    p += 1 + Body::kNodeRecordSize;
    g.parent[n] = static_cast<int>(p[0]);
    g.cut_u[n] = static_cast<int>(p[1]);
    g.cut_w[n] = static_cast<int>(p[2]);
    p += 3;
  }
  for (int i = 0; i < ne; ++i) {
    const int e = static_cast<int>(p[0]);
    if (e < 0 || e >= nelems) mismatch("element index out of range");
    g.active[e] = static_cast<int>(p[1]);
    for (int a = 0; a < 4; ++a)
      g.conn[4 * e + a] = static_cast<int>(p[2 + a]);
    g.elem_parent[e] = static_cast<int>(p[6]);
    const int size = static_cast<int>(p[7]);
    g.values[e].assign(p + 8, p + 8 + size);
    out.owner[e] = part;
    p += 8 + size;
  }
  return p;
}

// Body::pack_state's layout (fem/body.cpp) from the gathered parts.
std::vector<double> state_record(const GatheredParts& g, const GatheredBody& out, int mesh_elems,
                                 bool viscosity)
{
  const int nn = static_cast<int>(g.parent.size()), ne = static_cast<int>(g.active.size());
  std::vector<int> cuts;
  for (int n = 0; n < nn; ++n)
    if (g.cut_u[n] >= 0) cuts.insert(cuts.end(), {n, g.cut_u[n], g.cut_w[n]});
  const bool cut = ne > mesh_elems || !cuts.empty();
  const Body::Accounts& a = g.accounts;
  std::vector<double> r = {cut ? 5.0 : 4.0, double(nn), double(ne), a.time, a.external, a.contact};
  if (cut) {
    r.push_back(ne - mesh_elems);
    r.insert(r.end(), g.elem_parent.begin() + mesh_elems, g.elem_parent.end());
    r.push_back(static_cast<double>(cuts.size() / 3));
    r.insert(r.end(), cuts.begin(), cuts.end());
  }
  const int K = Body::kNodeRecordSize;
  for (int field : {0, 3, 6, 15}) // X, x, v, prescribed velocity (pack_node's order)
    for (int n = 0; n < nn; ++n)
      r.insert(r.end(), &g.node[K * size_t(n) + field], &g.node[K * size_t(n) + field] + 3);
  for (int field : {18, 19, 20}) // condition + 8 held, ramp, group
    for (int n = 0; n < nn; ++n)
      r.push_back(g.node[K * size_t(n) + field]);
  r.insert(r.end(), g.parent.begin(), g.parent.end());
  for (int n = 0; n < nn; ++n)
    r.push_back(g.node[K * size_t(n) + 24]); // mass
  r.insert(r.end(), g.conn.begin(), g.conn.end());
  r.insert(r.end(), g.active.begin(), g.active.end());
  const int tail = viscosity ? 3 : 0;
  double nstate = 0;
  for (const std::vector<double>& v : g.values)
    nstate += static_cast<double>(v.size()) - tail;
  r.push_back(nstate);
  for (const std::vector<double>& v : g.values)
    r.insert(r.end(), v.begin(), v.end() - tail);
  r.push_back(a.boundary);
  r.push_back(viscosity ? ne : 0);
  if (viscosity)
    for (int k = 3; k >= 1; --k) // work, last force, rate
      for (const std::vector<double>& v : g.values)
        r.push_back(v[v.size() - k]);
  const ErosionAccount& er = out.outputs.eroded;
  r.insert(r.end(), {double(er.elements), er.mass, er.energy, er.momentum[0], er.momentum[1],
                     er.momentum[2], a.shield_work, a.shield_hits});
  return r;
}

} // namespace

GatheredBody merge_part_wholes(const std::vector<double>& gathered, int global_nodes,
                               int global_elems, int mesh_elems, bool viscosity)
{
  GatheredParts g;
  g.node.assign(Body::kNodeRecordSize * static_cast<size_t>(global_nodes), 0.0);
  g.parent.assign(global_nodes, -2); // -2: no part sent it
  g.cut_u.assign(global_nodes, -1);
  g.cut_w.assign(global_nodes, -1);
  g.active.assign(global_elems, -1);
  g.conn.assign(4 * static_cast<size_t>(global_elems), -1);
  g.elem_parent.assign(global_elems, -1);
  g.values.resize(global_elems);
  GatheredBody out;
  out.owner.assign(global_elems, -1);
  const double* p = gathered.data();
  const double* end = p + gathered.size();
  for (bool first = true; p < end; first = false)
    p = read_part(p, g, out, first);
  for (int n = 0; n < global_nodes; ++n)
    if (g.parent[n] == -2) mismatch("without node " + std::to_string(n) + " (no part owned it)");
  for (int e = 0; e < global_elems; ++e)
    if (g.active[e] < 0) mismatch("without element " + std::to_string(e));
  std::sort(out.failed.begin(), out.failed.end());
  out.record = state_record(g, out, mesh_elems, viscosity);
  out.nodes = std::move(g.node);
  return out;
}

void restore_gathered(const GatheredBody& g, Body& whole)
{
  whole.unpack_state(g.record.data());
  for (int n = 0; n < whole.num_nodes(); ++n)
    whole.unpack_node(n, &g.nodes[Body::kNodeRecordSize * static_cast<size_t>(n)]);
  whole.set_outputs(g.outputs);
  whole.set_damage(g.damaged, g.failed);
}

std::vector<double> part_message_with_state(const Body& whole, const PartTopology& whole_topo,
                                            const std::vector<int>& elem_part,
                                            const std::vector<double>& packed_surface, int rank)
{
  const Mesh& mesh = whole.mesh();
  std::vector<double> out = {static_cast<double>(mesh.num_nodes()),
                             static_cast<double>(mesh.num_elems())};
  const MeshPart part = extract_part(mesh, elem_part, rank);
  pack_part(part, out);
  out.insert(out.end(), packed_surface.begin(), packed_surface.end());
  for (int g : part.global_node) {
    out.resize(out.size() + Body::kNodeRecordSize);
    whole.pack_node(g, out.data() + out.size() - Body::kNodeRecordSize);
    out.insert(out.end(), {double(whole_topo.node_parent[g]), double(whole_topo.cut_u[g]),
                           double(whole_topo.cut_w[g]), double(whole_topo.node_split[g])});
  }
  for (int g : part.global_elem) {
    out.insert(out.end(), {double(whole_topo.elem_parent[g]), double(whole_topo.elem_root[g]),
                           double(whole_topo.elem_fragment[g])});
    const int size = whole.element_record_size(g);
    out.push_back(size);
    out.resize(out.size() + size);
    whole.pack_element(g, out.data() + out.size() - size);
  }
  out.push_back(whole_topo.cut ? 1.0 : 0.0);
  put_accounts(share_of(whole.accounts(), rank == 0), out);
  Body::Outputs none;
  none.reactions.assign(whole.reactions().size(), 0.0);
  put_outputs(rank == 0 ? whole.outputs() : none, out);
  return out;
}

void unpack_part_message_state(const std::vector<double>& message, std::size_t at, Body& body,
                               const MeshPart& part, PartTopology& topo)
{
  const double* p = message.data() + at;
  const int nn = part.num_nodes(), ne = part.mesh.num_elems();
  topo.reset(nn, ne);
  topo.node_split.resize(nn);
  topo.elem_root.resize(ne);
  topo.elem_fragment.resize(ne);
  for (int n = 0; n < nn; ++n) {
    body.unpack_node(n, p);
    p += Body::kNodeRecordSize;
    topo.node_parent[n] = static_cast<int>(p[0]);
    topo.cut_u[n] = static_cast<int>(p[1]);
    topo.cut_w[n] = static_cast<int>(p[2]);
    topo.node_split[n] = static_cast<int>(p[3]);
    p += 4;
  }
  for (int e = 0; e < ne; ++e) {
    topo.elem_parent[e] = static_cast<int>(p[0]);
    topo.elem_root[e] = static_cast<int>(p[1]);
    topo.elem_fragment[e] = static_cast<int>(p[2]);
    const int size = static_cast<int>(p[3]);
    if (size != body.element_record_size(e)) mismatch("part message of another material");
    body.unpack_element(e, p + 4);
    p += 4 + size;
  }
  topo.cut = *p++ != 0.0;
  body.set_accounts(get_accounts(p));
  Body::Outputs o;
  add_outputs(p + kAccounts, o);
  body.set_outputs(o);
}

/* ----------------------------------------------------------------------
   restart records of a distributed body: one block per part
------------------------------------------------------------------------- */

namespace
{

constexpr int kOwnHead = 4; // topology set, cut, nodes, elements
constexpr int kOwnNode = 5; // global, parent, cut ends, split
constexpr int kOwnElem = 4; // global, parent, root, fragment

// The part's own state beside its pack_part_whole: every local node's topology, every element's,
// then Body::pack_node of each node it does not own (a shared node as this part holds it; the
// nodes it owns are in pack_part_whole). Topology fields are empty before the first change:
// zeros then, and set = 0.
std::vector<double> pack_own_part(const Body& body, const MeshPart& part, const PartTopology& topo)
{
  const int nn = part.num_nodes(), ne = body.mesh().num_elems();
  const bool set = !topo.elem_fragment.empty();
  std::vector<double> buf = {set ? 1.0 : 0.0, topo.cut ? 1.0 : 0.0, double(nn), double(ne)};
  for (int n = 0; n < nn; ++n)
    buf.insert(buf.end(),
               {double(part.global_node[n]), double(topo.node_parent[n]), double(topo.cut_u[n]),
                double(topo.cut_w[n]), set ? double(topo.node_split[n]) : 0.0});
  for (int e = 0; e < ne; ++e)
    buf.insert(buf.end(),
               {double(part.global_elem[e]), double(topo.elem_parent[e]),
                set ? double(topo.elem_root[e]) : 0.0, set ? double(topo.elem_fragment[e]) : 0.0});
  for (int n = 0; n < nn; ++n) {
    if (body.counted(n)) continue;
    buf.resize(buf.size() + Body::kNodeRecordSize);
    body.pack_node(n, buf.data() + buf.size() - Body::kNodeRecordSize);
  }
  return buf;
}

// The first owned node's entry (global, pack_node, parent, cut ends) of a pack_part_whole.
const double* whole_nodes(const double* w)
{
  const double* p = w + 3 + kAccounts;               // part, owned, elements, accounts
  p += kOutputs + 1 + static_cast<int>(p[kOutputs]); // outputs and reactions
  return p + 2 + static_cast<int>(p[1]);             // damaged points, failed elements
}

} // namespace

std::vector<double> pack_part_record(const Body& body, const MeshPart& part,
                                     const PartTopology& topo)
{
  const std::vector<double> whole = pack_part_whole(body, part, topo);
  const std::vector<double> own = pack_own_part(body, part, topo);
  std::vector<double> buf = {double(part.part), double(whole.size())};
  buf.insert(buf.end(), whole.begin(), whole.end());
  buf.push_back(static_cast<double>(own.size()));
  buf.insert(buf.end(), own.begin(), own.end());
  return buf;
}

std::vector<double> join_part_records(const std::vector<double>& gathered, int nparts,
                                      int global_nodes, int global_elems,
                                      const double (&driver)[kDriverValues])
{
  std::vector<double> rec = {kPartRecordsVersion, double(nparts), double(global_nodes),
                             double(global_elems)};
  rec.insert(rec.end(), driver, driver + kDriverValues);
  const size_t at = rec.size();
  rec.resize(at + global_elems, -1.0);
  int blocks = 0;
  for (size_t k = 0; k < gathered.size(); ++blocks) {
    const int part = static_cast<int>(gathered[k]);
    const size_t own = k + 2 + static_cast<size_t>(gathered[k + 1]);
    if (part < 0 || part >= nparts || own >= gathered.size()) mismatch("part block out of range");
    const double* p = &gathered[own + 1];
    const int nn = static_cast<int>(p[2]), ne = static_cast<int>(p[3]);
    const double* elems = p + kOwnHead + kOwnNode * static_cast<size_t>(nn);
    for (int e = 0; e < ne; ++e) {
      const int g = static_cast<int>(elems[kOwnElem * e]);
      if (g < 0 || g >= global_elems) mismatch("element index out of range");
      rec[at + g] = part;
    }
    k = own + 1 + static_cast<size_t>(gathered[own]);
  }
  for (int g = 0; g < global_elems; ++g)
    if (rec[at + g] < 0) mismatch("without element " + std::to_string(g));
  if (blocks != nparts)
    mismatch("of " + std::to_string(blocks) + " parts for " + std::to_string(nparts) + " ranks");
  rec.insert(rec.end(), gathered.begin(), gathered.end());
  return rec;
}

PartRecords read_part_records(const double* record)
{
  PartRecords r;
  r.nparts = static_cast<int>(record[1]);
  r.global_nodes = static_cast<int>(record[2]);
  r.global_elems = static_cast<int>(record[3]);
  if (r.nparts < 1 || r.global_nodes < 0 || r.global_elems < 0) mismatch("with a corrupt head");
  std::copy(record + 4, record + 4 + kDriverValues, r.driver);
  const double* p = record + 4 + kDriverValues;
  r.elem_part.assign(p, p + r.global_elems);
  p += r.global_elems;
  r.whole.assign(r.nparts, nullptr);
  r.own.assign(r.nparts, nullptr);
  r.whole_size.assign(r.nparts, 0);
  r.own_size.assign(r.nparts, 0);
  for (int b = 0; b < r.nparts; ++b) {
    const int part = static_cast<int>(p[0]);
    if (part < 0 || part >= r.nparts || r.whole[part]) mismatch("with a corrupt part block");
    r.whole_size[part] = static_cast<size_t>(p[1]);
    r.whole[part] = p + 2;
    p += 2 + r.whole_size[part];
    r.own_size[part] = static_cast<size_t>(p[0]);
    r.own[part] = p + 1;
    p += 1 + r.own_size[part];
  }
  return r;
}

std::vector<double> gathered_wholes(const PartRecords& r)
{
  std::vector<double> all;
  for (int k = 0; k < r.nparts; ++k)
    all.insert(all.end(), r.whole[k], r.whole[k] + r.whole_size[k]);
  return all;
}

void restore_own_part(const PartRecords& r, Body& body, const MeshPart& part, PartTopology& topo)
{
  const double* p = r.own[part.part];
  const bool set = p[0] != 0.0;
  const int nn = part.num_nodes(), ne = body.mesh().num_elems();
  if (static_cast<int>(p[2]) != nn || static_cast<int>(p[3]) != ne)
    mismatch("whose part " + std::to_string(part.part) + " is not this rank's");
  topo.reset(nn, ne);
  topo.cut = p[1] != 0.0;
  if (set) {
    topo.node_split.resize(nn);
    topo.elem_root.resize(ne);
    topo.elem_fragment.resize(ne);
  }
  p += kOwnHead;
  for (int n = 0; n < nn; ++n, p += kOwnNode) {
    if (static_cast<int>(p[0]) != part.global_node[n]) mismatch("with another part's nodes");
    topo.node_parent[n] = static_cast<int>(p[1]);
    topo.cut_u[n] = static_cast<int>(p[2]);
    topo.cut_w[n] = static_cast<int>(p[3]);
    if (set) topo.node_split[n] = static_cast<int>(p[4]);
  }
  for (int e = 0; e < ne; ++e, p += kOwnElem) {
    if (static_cast<int>(p[0]) != part.global_elem[e]) mismatch("with another part's elements");
    topo.elem_parent[e] = static_cast<int>(p[1]);
    if (set) {
      topo.elem_root[e] = static_cast<int>(p[2]);
      topo.elem_fragment[e] = static_cast<int>(p[3]);
    }
  }
  const double* owned = whole_nodes(r.whole[part.part]);
  for (int n = 0; n < nn; ++n) { // owned nodes from pack_part_whole, the others from here
    if (body.counted(n)) {
      if (static_cast<int>(owned[0]) != part.global_node[n]) mismatch("with another part's nodes");
      body.unpack_node(n, owned + 1);
      owned += 1 + Body::kNodeRecordSize + 3;
    } else {
      body.unpack_node(n, p);
      p += Body::kNodeRecordSize;
    }
  }
  // The part's accounts and output figures (pack_part_whole: part, owned, elements, accounts).
  const double* w = r.whole[part.part];
  body.set_accounts(get_accounts(w + 3));
  Body::Outputs o;
  add_outputs(w + 3 + kAccounts, o);
  body.set_outputs(o);
}

} // namespace fracdem
