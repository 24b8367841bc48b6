// The contact scene of a run's replicated bodies, its members and the pairs carried between runs.
#include "body/contact_coordinator.h"

#include <algorithm>
#include <cstdio>
#include <exception>

#include "body/pair_records.h"

namespace fracdem
{

std::shared_ptr<ContactCoordinator>
ContactCoordinator::renew(const std::shared_ptr<ContactCoordinator>& last,
                          const std::vector<const void*>& keys, std::vector<SceneBody> members,
                          Settings settings)
{
  auto c = std::make_shared<ContactCoordinator>();
  const bool same = last && last->active() && last->keys_ == keys;
  // A new run with the same bodies: the pieces' contacts, spread over the ranks' parts, are
  // gathered first (the new scene starts without a partition), and the new scene takes the
  // contacts between the bodies. A scene not yet evaluated (a second set-up before a step, e.g.
  // write_restart's) keeps those carried into it.
  const bool evaluated = same && last->scene_->size() > 0;
  c->continues_ = same && (evaluated || last->continues_);
  c->keys_ = keys;
  c->members_ = std::move(members);
  c->settings_ = std::move(settings);
  if (c->continues_ && evaluated) {
    for (int m = 0; m < last->scene_->size(); ++m)
      last->scene_->gather_self_state(m);
    c->carried_ = last->scene_pair_records();
  } else if (same) {
    c->carried_ = last->carried_;
  } else {
    c->take_restored_pairs(); // after a restart: the file's contacts of these bodies
  }
  c->scene_ = std::make_unique<ContactScene>();
  c->pending_ = true;
  return c;
}

void ContactCoordinator::disband()
{
  scene_.reset();
  keys_.clear();
  members_.clear();
  carried_.clear();
  continues_ = pending_ = false;
}

int ContactCoordinator::index_of(const void* key) const
{
  const auto it = std::find(keys_.begin(), keys_.end(), key);
  return it == keys_.end() ? -1 : static_cast<int>(it - keys_.begin());
}

// The pair (a, b), a < b, takes body a's settings and friction, as body a computed it before the
// scene.
void ContactCoordinator::configure_if_pending()
{
  if (!pending_ || !scene_) return;
  pending_ = false;
  const ContactBalance& balance = settings_.balance;
  const int nprocs = settings_.comm.nprocs;
  if (balance.parts > 1 && nprocs > 1 && balance.parts != nprocs)
    settings_.fail("keyword 'contact_balance': 'parts " + std::to_string(balance.parts) +
                   "' models that many ranks in a one-rank run; under " + std::to_string(nprocs) +
                   " ranks the parts are the ranks (leave 'parts' out)");
  const size_t n = members_.size();
  const std::vector<SceneBody>& bodies = members_;
  std::vector<SceneMember> members(n);
  std::vector<SurfaceContactOptions> pairs(n * (n - 1) / 2);
  for (size_t b = 0; b < n; ++b) {
    members[b] = {bodies[b].surface, bodies[b].self, bodies[b].edges};
    for (size_t a = 0; a < b; ++a)
      pairs[ContactScene::pair_index(static_cast<int>(a), static_cast<int>(b))] =
          bodies[a].options(bodies[b].surface_type, bodies[b].youngs,
                            (*bodies[a].friction)(bodies[a].surface_type, bodies[b].surface_type));
  }
  try {
    scene_->configure(std::move(members), std::move(pairs), balance, settings_.comm);
    restore_pairs();
  } catch (const std::exception& e) {
    settings_.fail(e.what());
  }
  const int parts = scene_->parts();
  if (n < 2 && parts < 2) return;
  char line[256];
  if (parts == 1)
    std::snprintf(line, sizeof line,
                  "contact scene of %zu bodies, one search over their surfaces; contact work on "
                  "one rank\n",
                  n);
  else
    std::snprintf(line, sizeof line,
                  "contact scene of %zu bodies, one search over their surfaces; contact work over "
                  "%d %s, %s model, thresh %g, every %d\n",
                  n, parts, nprocs > 1 ? "ranks" : "model parts",
                  balance.model == ContactBalance::APriori ? "a priori" : "a posteriori",
                  balance.thresh, balance.every);
  settings_.print(line);
}

int ContactCoordinator::evaluate(int k, std::int64_t step, double dt)
{
  configure_if_pending();
  std::vector<ContactBodyState> states(members_.size());
  for (size_t m = 0; m < members_.size(); ++m) {
    Body& b = *members_[m].body;
    const int i = static_cast<int>(m);
    double* f = i == k ? b.contact_forces() : i > k ? b.pending_contact_forces() : nullptr;
    states[m] = {b.positions().data(), b.velocities().data(), b.masses().data(), f};
  }
  return scene_->evaluate_body(k, states, step, dt);
}

void ContactCoordinator::invalidate()
{
  if (scene_) scene_->invalidate();
}

void ContactCoordinator::gather_self_state(int k)
{
  if (scene_ && scene_->size() > k) scene_->gather_self_state(k);
}

bool ContactCoordinator::replays() const
{
  // A partner gone would still push; after a restart, where the file held their pairs.
  if (members_.size() > 1 && !continues_) return false;
  for (const SceneBody& m : members_)
    if (!*m.contacts_held) return false;
  return true;
}

// Every pair of the scene (every rank enters: the state is summed over the parts holding it).
std::vector<double> ContactCoordinator::scene_pair_records() const
{
  std::vector<double> out;
  const int n = scene_->size();
  for (int b = 1; b < n; ++b)
    for (int a = 0; a < b; ++a)
      put_pair({members_[a].id, members_[b].id, scene_->pair_state(a, b)}, out);
  return out;
}

// A scene not evaluated since its set-up (write_restart sets the bodies up before it writes) has
// its state still to take.
std::vector<double> ContactCoordinator::pair_records() const
{
  if (!scene_ || members_.size() < 2) return {};
  return scene_->size() > 0 ? scene_pair_records() : carried_;
}

// After a restart: where the files hold every pair of these bodies (same fix IDs, whichever body
// held them, replicated or distributed), the scene goes on with them and its set-up replays the
// held forces; otherwise the pairs start afresh.
void ContactCoordinator::take_restored_pairs()
{
  std::vector<PairRecord> records;
  const std::vector<SceneBody>& bodies = members_;
  try {
    for (const SceneBody& b : bodies)
      if (b.restored)
        for (PairRecord& r : read_pairs(*b.restored))
          records.push_back(std::move(r));
  } catch (const std::exception& e) {
    settings_.fail(e.what());
  }
  if (records.empty() || bodies.size() < 2) return;
  std::vector<double> carried;
  for (size_t b = 1; b < bodies.size(); ++b)
    for (size_t a = 0; a < b; ++a) {
      const PairRecord* r = find_pair(records, bodies[a].id, bodies[b].id);
      if (!r) return;
      put_pair(*r, carried);
    }
  carried_ = std::move(carried);
  continues_ = true;
}

// At the scene's first evaluation: the carried pairs into the new scene (configured: its pairs
// exist); the restored records are spent.
void ContactCoordinator::restore_pairs()
{
  std::vector<std::string> ids;
  for (const SceneBody& m : members_)
    ids.push_back(m.id);
  for (const PairRecord& r : read_pairs(carried_)) {
    const int a = static_cast<int>(std::find(ids.begin(), ids.end(), r.first) - ids.begin());
    const int b = static_cast<int>(std::find(ids.begin(), ids.end(), r.second) - ids.begin());
    if (a < b && b < static_cast<int>(ids.size())) scene_->restore_pair_state(a, b, r.state);
  }
  carried_.clear();
  drop_restored_pairs();
}

void ContactCoordinator::drop_restored_pairs()
{
  for (const SceneBody& m : members_)
    if (m.restored) m.restored->clear();
}

} // namespace fracdem
