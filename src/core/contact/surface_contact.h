// Contact between the surfaces of a body's pieces (crack faces, fragments, self contact): node to
// edge in 2D, node to facet in 3D, penalty normal force with Coulomb friction.
#pragma once

#include <utility>
#include <vector>

#include "contact/contact_search.h"
#include "fem/mesh.h"

namespace fracdem
{

struct SurfaceContactOptions {
  // Normal penalty: force per unit penetration = penalty_scale * E * t, with t the thickness
  // (plane), 2 pi r at the node (axisymmetric, full-ring forces) or the facet's size (3D). With
  // scale 1 the contact spring is about as stiff as an element, so the stable step is unchanged.
  double youngs = 0;
  double penalty_scale = 1.0;
  double thickness = 1.0;
  bool axisymmetric = false;
  double friction = 0; // Coulomb coefficient
};

// Outward unit normal of a triangle facet at positions x (zero for a degenerate one).
void facet_unit_normal(const double* x, const Facet& fc, double* n);

// A boundary edge of a 3D surface with its two boundary facets (edge_contact.h). `feature`: the
// edge is convex and its facets' reference normals differ by at least kFeatureAngleDeg, so it
// can meet another edge where no node meets a facet; flat and concave edges are left to
// node-to-facet contact.
struct SurfaceEdge {
  int n[2];
  int facet[2];
  double reach; // the smaller of its facets' reaches
  bool feature;
};

// Every boundary node is checked against the boundary facets that share no node with the facets
// around it (its own surface neighbourhood: a corner is not a contact). A node is
// in contact with a facet when its projection falls on the facet (barycentric coordinates >=
// -1 %) and it lies behind the facet's outward plane by less than half the altitude of the
// facet's element over it (so a node at the element's far vertex, e.g. the twin of a split
// node, is never taken for a penetration); of
// such facets the deepest wins (lowest index among equals), so a node has at most one contact.
// Crack faces start closed (a split node and its copy coincide): they touch with zero
// penetration and push apart only when the crack would close beyond contact.
// Self contact of a node with a facet that has the node's split copy (its twin: the same site)
// as a corner: the node lies at that corner of every facet around its copy, so it projects onto
// all of them, and on a rough crack it lies behind the plane of some of them for most directions
// of opening or sliding; taking that depth along the tilted facet's normal (the rule before)
// made energy (test_fracture_cut's torn tet4 bar with friction 0: +0.062 J of contact work by
// step 4000, 481704 of its 502004 node-to-facet contacts of this kind). Such a pair is a contact
// between the twins instead: penetration = their closing along the crack's normal at them (the
// copy's vertex normal less the node's: faces they share cancel), the reaction on the copy.
// 3D only: in 2D the rule before made no energy, and the crack paths it gives are recorded.
// Penetration that the motion of the step cannot explain (a contact that appears already deep:
// after an erosion exposes a facet, a node passing a corner onto the next facet, pieces placed
// overlapping) is not turned into force: the excess over twice the step's approach becomes an
// offset that the penalty measures from, and the offset shrinks as the penetration does (as
// LS-DYNA's IGNORE option treats initial penetrations). Without it such a contact releases
// penalty energy that no work put in; with it the contact energy stays bounded by the work
// of the approach. The offset is kept per node while the node stays in contact.
// The boundary of one body for surface contact: facets, their nodes, facets around each node,
// and in 3D the edges between two boundary facets (edges of more or fewer facets are left out).
struct ContactSurface {
  static constexpr double kFeatureAngleDeg = 30;
  std::vector<Facet> facets;
  std::vector<int> nodes; // boundary nodes and free nodes (all elements eroded), ascending
  std::vector<int> incident_offset, incident; // per mesh node: boundary facets around it
  std::vector<double> reach; // per facet: deepest accepted contact, half its element altitude
  double max_reach = 0;
  std::vector<SurfaceEdge> edges; // 3D only; sorted by (lower node, higher node)
  double max_edge_reach = 0;      // over the feature edges
  // Per mesh node: the lowest-numbered surface node at the same reference position, the node
  // itself elsewhere. A split node's copies keep their parent's reference position (so do the
  // nodes that bisect the two faces' copies of one edge at one ratio): one site per point of a
  // closed crack, whose faces' edges meet there (edge_contact.h).
  std::vector<int> site;
  void build(const Mesh& mesh, const std::vector<Facet>& boundary);
  // The same from its parts: per facet its reach (facet_reach), reference positions X of
  // num_nodes nodes (only the surface's are read), the free nodes (free_nodes). A distributed
  // body builds its whole surface this way from what its parts hold (global node numbers).
  void build(const std::vector<Facet>& boundary, const std::vector<double>& reaches,
             const double* X, int num_nodes, const std::vector<int>& free);
  // Whether `facet` shares a node with a facet around `node` (same body only).
  bool neighbourhood(int node, int facet) const;
  // The corner of `facet` at `node`'s site that is not `node` (its split copy), or -1.
  int twin_corner(int node, int facet) const;
  // Unit outward normal at a surface node: the normalised sum of the unit normals of the
  // facets around it; false where they nearly cancel.
  bool vertex_normal(const double* x, int node, double* n) const;
  int site_of(int node) const
  {
    return static_cast<size_t>(node) < site.size() ? site[node] : node;
  }

private:
  void build_sites(const double* X, int num_nodes);
  void build_edges(const double* X);
};

// Deepest contact a facet accepts: half the altitude of its element over it (mesh.X).
double facet_reach(const Mesh& mesh, const Facet& fc);
// Nodes of eroded elements only (they still hit surfaces as contacting nodes), ascending.
std::vector<int> free_nodes(const Mesh& mesh);

// A body's nodal state as surface contact sees it; forces are added to f (null: not added).
struct ContactBodyState {
  const double* x;
  const double* v;
  const double* m;
  double* f;
};

// Nodes of one surface against the facets of another (or the same: self contact).
class SurfaceContact
{
public:
  void configure(const SurfaceContactOptions& options) { opt_ = options; }
  const SurfaceContactOptions& options() const { return opt_; }
  // After any topology change of either side: the search starts afresh.
  void invalidate() { stale_ = true; }
  // Adds the contact forces of `nodes_of`'s nodes on `facets_of`'s facets: on the node along
  // the facet normal, the reaction on the facet's nodes by the projection's barycentric weights
  // (momentum balance to round-off), friction from the relative tangential velocity, capped so
  // that it cannot reverse that velocity within the step. `self`: the same body (its own surface
  // neighbourhood excluded). Returns the number of contacts.
  int evaluate(const ContactSurface& nodes_of, const ContactBodyState& a,
               const ContactSurface& facets_of, const ContactBodyState& b, bool self, double dt);
  // What resolve() did: candidate facets tested and contacts evaluated (forces applied).
  struct Counts {
    long tests = 0, contacts = 0;
  };
  // evaluate() without its own search: the given candidates (index into nodes_of.nodes, facet
  // index), sorted by node then facet, as a search over both surfaces (contact/contact_scene.h)
  // found them. owner (per entry of nodes_of.nodes; null: every node is this caller's): only the
  // nodes with owner[s] == part are resolved, so that parts that share the candidates evaluate
  // each contact once. tests / contacts (per node, null: not counted) get each resolved node's
  // counts added. One call per evaluation on every part (the contacts' continuity counts them).
  Counts resolve(const ContactSurface& nodes_of, const ContactBodyState& a,
                 const ContactSurface& facets_of, const ContactBodyState& b, bool self, double dt,
                 const std::pair<int, int>* cand, std::size_t ncand, const int* owner = nullptr,
                 int part = 0, double* tests = nullptr, double* contacts = nullptr);
  // The per-node contact state (for restart): appends, for every node in contact at the last
  // evaluation, (node, penetration, offset). After unpack_state of those doubles (a multiple of
  // 3; none: a fresh object) the next evaluate() continues these contacts exactly as this object
  // would; other state (options, search) is not part of it.
  void pack_state(std::vector<double>& out) const;
  void unpack_state(const double* in, size_t n);
  // The same state densely, 3 doubles per entry of `nodes` (in contact at the last evaluation
  // 1 / 0, penetration, offset); export_state leaves zeros for the nodes where keep(s) is false,
  // so that a sum over the parts that each kept their own nodes is the whole state, which
  // import_state sets (contact/contact_scene.cpp moves contacts between parts this way).
  template <class Keep>
  void export_state(const std::vector<int>& nodes, Keep keep, double* out) const
  {
    for (size_t s = 0; s < nodes.size(); ++s) {
      const size_t node = static_cast<size_t>(nodes[s]);
      const bool on =
          keep(s) && eval_ > 0 && node < last_eval_.size() && last_eval_[node] == eval_ - 1;
      out[3 * s] = on ? 1.0 : 0.0;
      out[3 * s + 1] = on ? last_depth_[node] : 0.0;
      out[3 * s + 2] = on ? offset_[node] : 0.0;
    }
  }
  void import_state(const std::vector<int>& nodes, const double* in);

private:
  struct Touch {
    int facet = -1;
    double depth = 0, normal[3], w[3];
    double vr[3]; // velocity of the node relative to the facet's contact point
  };
  // corner >= 0: that corner of fc is the node's split copy, vn its vertex normal.
  bool touch(const double* q, const Facet& fc, double reach, const double* x, Touch& t,
             int corner = -1, const double* vn = nullptr) const;
  bool twin_normal(const ContactSurface& s, int node, int copy, const double* x, double* n) const;
  void apply(int node, const Touch& t, const Facet& fc, const ContactBodyState& a,
             const ContactBodyState& b, double dt) const;
  double stiffness(const double* q, const Facet& fc, const double* x) const;
  void rebuild_search(const ContactSurface& facets_of, const double* xb, int ns, double buffer);
  double effective_depth(int node, const Touch& t, double dt);

  SurfaceContactOptions opt_;
  BufferedSearch search_{0.0};
  std::vector<double> sphere_, sx_, sxb_;
  bool stale_ = true;
  // Per node of the contacting side: penetration and offset at its last contact, and the
  // evaluation that contact belongs to (a contact continues only from the previous evaluation).
  std::vector<double> last_depth_, offset_;
  std::vector<long> last_eval_;
  long eval_ = 0;
};

} // namespace fracdem
