// Contact between the surfaces of a body's pieces (crack faces, fragments, self contact): node to
// edge in 2D, node to facet in 3D, penalty normal force with Coulomb friction.
#pragma once

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

// Every boundary node is checked against the boundary facets that share no node with the facets
// around it (its own surface neighbourhood: a corner is not a contact). A node is
// in contact with a facet when its projection falls on the facet (barycentric coordinates >=
// -1 %) and it lies behind the facet's outward plane by less than half the facet's size; of
// such facets the deepest wins (lowest index among equals), so a node has at most one contact.
// Crack faces start closed (a split node and its copy coincide): they touch with zero
// penetration and push apart only when the crack would close beyond contact.
class SurfaceContact
{
public:
  void configure(const SurfaceContactOptions& options) { opt_ = options; }
  // After any topology change: the facets (boundary of the active mesh) and their nodes.
  void rebuild(const Mesh& mesh, const std::vector<Facet>& facets);
  // Adds the contact forces into f (3 per node): on the node along the facet normal, the
  // reaction on the facet's nodes by the projection's barycentric weights (momentum balance to
  // round-off), friction from the relative tangential velocity, capped so that it cannot
  // reverse that velocity within the step (m: node masses). Returns the number of contacts.
  int evaluate(const double* x, const double* v, const double* m, double dt, double* f);

private:
  struct Touch {
    int facet = -1;
    double depth = 0, normal[3], w[3];
  };
  bool touch(int node, int facet, const double* x, Touch& t) const;
  void apply(int node, const Touch& t, const double* x, const double* v, const double* m, double dt,
             double* f) const;
  double stiffness(int node, int facet, const double* x) const;

  SurfaceContactOptions opt_;
  const Mesh* mesh_ = nullptr;
  std::vector<Facet> facets_;
  std::vector<int> nodes_;                      // boundary nodes
  std::vector<int> incident_offset_, incident_; // per mesh node: boundary facets around it
  bool neighbourhood(int node, int facet) const;
  BufferedSearch search_{0.0};
  double buffer_ = 0;
  std::vector<double> sphere_, sx_;
  bool stale_ = true;
};

} // namespace fracdem
