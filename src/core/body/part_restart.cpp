// Restart records of distributed bodies (see part_restart.h).
#include "body/part_restart.h"

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

std::vector<double> pack_part_state(const Body& body, const MeshPart* part)
{
  const int nn = body.num_nodes(), ne = body.mesh().num_elems();
  int owned = 0;
  for (int n = 0; n < nn; ++n)
    owned += body.counted(n) ? 1 : 0;
  std::vector<double> buf = {double(owned), double(ne)};
  put_accounts(body.accounts(), buf);
  const std::vector<double>& x = body.positions();
  const std::vector<double>& v = body.velocities();
  for (int n = 0; n < nn; ++n) {
    if (!body.counted(n)) continue; // its owner writes it
    buf.push_back(global_node(part, n));
    buf.insert(buf.end(), &x[3 * n], &x[3 * n] + 3);
    buf.insert(buf.end(), &v[3 * n], &v[3 * n] + 3);
  }
  for (int e = 0; e < ne; ++e) {
    const int size = body.element_record_size(e);
    buf.push_back(global_elem(part, e));
    buf.push_back(size);
    buf.resize(buf.size() + size);
    body.pack_element(e, buf.data() + buf.size() - size);
  }
  return buf;
}

std::vector<double> merge_part_states(const std::vector<double>& gathered, int global_nodes,
                                      int global_elems)
{
  std::vector<double> motion(6 * static_cast<size_t>(global_nodes));
  std::vector<char> node_seen(global_nodes, 0);
  std::vector<std::vector<double>> elems(global_elems);
  std::vector<char> elem_seen(global_elems, 0);
  double acc[kAccounts] = {0, 0, 0, 0, 0, 0};
  bool first = true;
  for (size_t k = 0; k < gathered.size();) {
    const double* p = &gathered[k];
    const int owned = static_cast<int>(p[0]), ne = static_cast<int>(p[1]);
    for (int i = first ? 0 : 1; i < kAccounts; ++i) // the clock is every part's
      acc[i] += p[2 + i];
    first = false;
    p += 2 + kAccounts;
    for (int i = 0; i < owned; ++i, p += 7) {
      const int g = static_cast<int>(p[0]);
      if (g < 0 || g >= global_nodes) mismatch("node index out of range");
      std::copy(p + 1, p + 7, &motion[6 * static_cast<size_t>(g)]);
      node_seen[g] = 1;
    }
    for (int i = 0; i < ne; ++i) {
      const int g = static_cast<int>(p[0]), size = static_cast<int>(p[1]);
      if (g < 0 || g >= global_elems) mismatch("element index out of range");
      elems[g].assign(p + 2, p + 2 + size);
      elem_seen[g] = 1;
      p += 2 + size;
    }
    k = static_cast<size_t>(p - gathered.data());
  }
  for (int g = 0; g < global_nodes; ++g)
    if (!node_seen[g]) mismatch("without node " + std::to_string(g) + " (no part owned it)");
  for (int g = 0; g < global_elems; ++g)
    if (!elem_seen[g]) mismatch("without element " + std::to_string(g));
  std::vector<double> rec = {kPartsRecordVersion, double(global_nodes), double(global_elems)};
  rec.insert(rec.end(), acc, acc + kAccounts);
  rec.insert(rec.end(), motion.begin(), motion.end());
  for (const std::vector<double>& e : elems) {
    rec.push_back(static_cast<double>(e.size()));
    rec.insert(rec.end(), e.begin(), e.end());
  }
  return rec;
}

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

} // namespace fracdem
