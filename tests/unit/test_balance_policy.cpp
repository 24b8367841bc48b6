// Unit tests of the balance policy of fix balance/graph: the keyword table, the cost models and
// graph weights, the check schedule and trigger, the partition strategy and the report.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "balance/balance_check.h"
#include "balance/balance_report.h"
#include "balance/balance_restart.h"
#include "balance/balance_spec.h"
#include "balance/cost_pricing.h"
#include "balance/gathered_graph.h"
#include "balance/partition_strategy.h"
#include "test_support.h"

using namespace fracdem::balance;
using fracdem_test::grid_graph;

namespace
{

std::string spec_error(const std::vector<std::string>& words)
{
  try {
    parse_balance_spec(words);
  } catch (const BalanceSpecError& e) {
    return e.what();
  }
  return "no error";
}

std::vector<std::string> csv_fields(const std::string& line)
{
  std::vector<std::string> out;
  std::stringstream ss(line.substr(0, line.find('\n')));
  for (std::string f; std::getline(ss, f, ',');)
    out.push_back(f);
  return out;
}

// Three particles: 0 and 1 touch, 1 and 2 are neighbours only; particle 2 touches a wall.
WorkCounts three_particles()
{
  WorkCounts w;
  w.reset(3, 1);
  w.potential = {1, 2, 1};
  w.contacts = {1, 1, 0};
  w.wall_contacts = {0, 0, 1};
  return w;
}

} // namespace

TEST(BalanceSpec, DefaultsAndEveryKeyword)
{
  const BalanceSpec d = parse_balance_spec({"10", "1.05"});
  EXPECT_EQ(d.every, 10);
  EXPECT_DOUBLE_EQ(d.threshold, 1.05);
  EXPECT_EQ(d.graph_model, GraphModel::APosteriori);
  EXPECT_EQ(d.cost_model, CostModel::Timed);
  EXPECT_EQ(d.partitioner, Partitioner::Metis);
  EXPECT_EQ(d.strategy, Strategy::Auto);
  EXPECT_DOUBLE_EQ(d.cell_factor, 2.0);
  EXPECT_TRUE(d.out_file.empty());
  const BalanceSpec s = parse_balance_spec(
      {"5", "1.2", "model", "apriori", "cost", "fitted", "partitioner", "layers", "repartition",
       "scratch", "cells", "1.5", "insert_region", "a", "insert_region", "b", "out", "b.csv"});
  EXPECT_EQ(s.graph_model, GraphModel::APriori);
  EXPECT_EQ(s.cost_model, CostModel::Fitted);
  EXPECT_EQ(s.partitioner, Partitioner::Layers);
  EXPECT_EQ(s.strategy, Strategy::Scratch);
  EXPECT_DOUBLE_EQ(s.cell_factor, 1.5);
  EXPECT_EQ(s.insert_regions, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(s.out_file, "b.csv");
}

TEST(BalanceSpec, ErrorsNameTheKeywordAndWhatWasExpected)
{
  EXPECT_EQ(spec_error({"0", "1.1"}), "Nevery must be a positive integer, got '0'");
  EXPECT_EQ(spec_error({"99999999999", "1.1"}),
            "Nevery must be a positive integer, got '99999999999'");
  EXPECT_EQ(spec_error({"10", "0.9"}), "thresh must be a number >= 1.0 (max/avg work), got '0.9'");
  EXPECT_EQ(spec_error({"10", "1.1", "cost", "guess"}),
            "keyword 'cost': expected counts, calibrated, timed or fitted, got 'guess'");
  EXPECT_EQ(spec_error({"10", "1.1", "colour", "red"}),
            "unknown keyword 'colour' (expected model, cost, partitioner, repartition, cells, "
            "counts, insert_region or out)");
  EXPECT_EQ(spec_error({"10", "1.1", "counts", "guess"}),
            "keyword 'counts': expected pair or recount, got 'guess'");
  EXPECT_EQ(spec_error({"10", "1.1", "model", "apriori", "model", "aposteriori"}),
            "keyword 'model' given twice");
  EXPECT_EQ(spec_error({"10", "1.1", "model"}), "keyword 'model' needs a value");
  EXPECT_NE(spec_error({"10", "1.1", "cells", "0.5"}).find("keyword 'cells': expected 0"),
            std::string::npos);
  EXPECT_NE(spec_error({"10", "1.1", "partitioner", "scotch", "repartition", "refine"})
                .find("with 'partitioner scotch' each repartition is one SCOTCH_graphRepart"),
            std::string::npos);
  EXPECT_NE(spec_error({"10", "1.1", "partitioner", "rcb", "cells", "0"})
                .find("keyword 'partitioner rcb' cuts the cell grid by coordinates"),
            std::string::npos);
}

// partitioner ptscotch: one vertex per particle (cells left out means cells 0), no `repartition`.
TEST(BalanceSpec, DistributedPartitionerKeepsParticleVertices)
{
  const BalanceSpec s = parse_balance_spec({"10", "1.1", "partitioner", "ptscotch"});
  EXPECT_EQ(s.partitioner, Partitioner::PtScotch);
  EXPECT_EQ(s.cell_factor, 0.0);
  EXPECT_EQ(parse_balance_spec({"10", "1.1", "partitioner", "ptscotch", "cells", "0"}).cell_factor,
            0.0);
  EXPECT_NE(spec_error({"10", "1.1", "partitioner", "ptscotch", "cells", "2"})
                .find("keyword 'partitioner ptscotch' partitions one vertex per particle"),
            std::string::npos);
  EXPECT_NE(spec_error({"10", "1.1", "partitioner", "ptscotch", "repartition", "scratch"})
                .find("'partitioner ptscotch' partitions on all ranks in one call"),
            std::string::npos);
  // Zoltan's geometric methods cut the particles' positions: no cells, no `repartition` (unlike
  // the gathered rcb, which needs cells).
  EXPECT_EQ(parse_balance_spec({"10", "1.1", "partitioner", "zoltan-rcb"}).cell_factor, 0.0);
  EXPECT_NE(spec_error({"10", "1.1", "partitioner", "zoltan-hsfc", "cells", "2"})
                .find("keyword 'partitioner zoltan-hsfc' partitions one vertex per particle"),
            std::string::npos);
  EXPECT_NE(spec_error({"10", "1.1", "partitioner", "zoltan-rib", "repartition", "auto"})
                .find("'partitioner zoltan-rib' partitions on all ranks in one call"),
            std::string::npos);
  // The default elsewhere is unchanged: cells two cutoffs wide.
  EXPECT_EQ(parse_balance_spec({"10", "1.1", "partitioner", "metis"}).cell_factor, 2.0);
}

// The labels from an overlap table alone are those relabel_max_overlap gives from the vertices.
TEST(PartitionStrategy, OverlapLabelsAgreeWithRelabellingTheVertices)
{
  const int nparts = 4;
  std::vector<int> owner, fresh;
  std::vector<double> w;
  std::vector<double> overlap(nparts * nparts, 0.0);
  for (int v = 0; v < 97; ++v) {
    owner.push_back(v % nparts), fresh.push_back((v * 7 + v / 5) % nparts), w.push_back(1 + v % 3);
    overlap[fresh.back() * nparts + owner.back()] += w.back();
  }
  const std::vector<int> label = max_overlap_labels(overlap, nparts);
  const std::vector<int> relabelled = relabel_max_overlap(fresh, owner, w, nparts);
  for (int v = 0; v < 97; ++v)
    EXPECT_EQ(label[fresh[v]], relabelled[v]) << "vertex " << v;
  EXPECT_THROW(max_overlap_labels(std::vector<double>(3, 0.0), 2), std::invalid_argument);
}

TEST(PartitionStrategy, TableRejectsAnUnknownPartitionerByName)
{
  EXPECT_EQ(find_partitioner("metis").id, Partitioner::Metis);
  EXPECT_TRUE(find_partitioner("scotch").repartitions);
  EXPECT_TRUE(find_partitioner("rcb").geometric);
  EXPECT_TRUE(find_partitioner("layers").geometric);
  EXPECT_FALSE(find_partitioner("metis").geometric);
  EXPECT_TRUE(find_partitioner("ptscotch").distributed);
  EXPECT_FALSE(find_partitioner("metis").distributed);
  EXPECT_STREQ(find_partitioner("ptscotch").package, "libptscotch-dev");
  EXPECT_TRUE(find_partitioner("zoltan-phg").distributed);
  EXPECT_EQ(find_partitioner("zoltan-graph").id, Partitioner::ZoltanGraph);
  // Zoltan's geometric methods: distributed, cut by coordinates, one call per repartition.
  for (const char* name : {"zoltan-rcb", "zoltan-rib", "zoltan-hsfc"}) {
    const PartitionerInfo& p = find_partitioner(name);
    EXPECT_TRUE(p.distributed && p.geometric && p.repartitions) << name;
    EXPECT_STREQ(p.package, "libtrilinos-zoltan-dev") << name;
    EXPECT_EQ(&partitioner_info(p.id), &p) << name;
  }
  EXPECT_STREQ(find_partitioner("zoltan-rcb").zoltan_method, "RCB");
  EXPECT_STREQ(find_partitioner("zoltan-rib").zoltan_method, "RIB");
  EXPECT_STREQ(find_partitioner("zoltan-hsfc").zoltan_method, "HSFC");
  EXPECT_STREQ(find_partitioner("zoltan-phg").zoltan_method, "HYPERGRAPH");
  EXPECT_EQ(find_partitioner("metis").zoltan_method, nullptr);
  const char* expected = "keyword 'partitioner': expected metis or scotch or rcb or layers or "
                         "ptscotch or zoltan-phg or zoltan-graph or zoltan-rcb or zoltan-rib or "
                         "zoltan-hsfc, got 'chaco'";
  try {
    find_partitioner("chaco");
    FAIL() << "an unknown partitioner was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), expected);
  }
  EXPECT_EQ(spec_error({"10", "1.1", "partitioner", "chaco"}), expected);
}

// The strategy is the partitioners' own calls in a fixed order: `scratch` with METIS is METIS
// k-way relabelled to the current owners, `refine` the diffusion from them; the prediction is the
// partition's own max/avg and edge cut.
TEST(PartitionStrategy, AgreesWithThePartitionersCalledDirectly)
{
  const Graph g = grid_graph(12, 12);
  std::vector<int> owner(144);
  for (int v = 0; v < 144; ++v)
    owner[v] = v % 12 < 8 ? 0 : 1; // two strips, 2:1
  const std::vector<double> load(g.vwgt.begin(), g.vwgt.end());

  const PartitionResult scratch =
      PartitionStrategy(Partitioner::Metis, Strategy::Scratch).partition(g, owner, 2);
  const std::vector<int> direct =
      relabel_max_overlap(partition_kway(g, 2, kPartitionTolerance), owner, load, 2);
  EXPECT_EQ(scratch.part, direct);
  EXPECT_DOUBLE_EQ(scratch.predicted_imbalance, imbalance(part_loads(load, direct, 2)));
  EXPECT_DOUBLE_EQ(scratch.edge_cut, static_cast<double>(edge_cut(g, direct)));

  const PartitionResult refined =
      PartitionStrategy(Partitioner::Metis, Strategy::Refine).partition(g, owner, 2);
  std::vector<int> diffused = owner;
  refine_partition(g, diffused, 2, kPartitionTolerance, kRefinePasses);
  EXPECT_EQ(refined.part, diffused);
  EXPECT_LE(refined.predicted_imbalance, kPartitionTolerance);
  // auto diffuses below kRefineBelow (the strips are 1.33): the same as refine here.
  EXPECT_EQ(PartitionStrategy(Partitioner::Metis, Strategy::Auto).partition(g, owner, 2).part,
            diffused);
}

TEST(CostModel, WeightsOfAHandBuiltGraph)
{
  InteractionCosts c;
  c.particle = 4, c.wall_check = 0.5, c.pair_check = 1, c.sphere_contact = 20;
  c.wall_contact = 10, c.facet_check = 3, c.facet_contact = 30;
  const WorkCounts w = three_particles();
  const RankWork work = price_counts(c, w);
  // particle + wall check + pair checks + contacts (+ wall contact)
  ASSERT_EQ(work.cost.size(), 3u);
  EXPECT_DOUBLE_EQ(work.cost[0], 4 + 0.5 + 1 + 20);
  EXPECT_DOUBLE_EQ(work.cost[1], 4 + 0.5 + 2 + 20);
  EXPECT_DOUBLE_EQ(work.cost[2], 4 + 0.5 + 1 + 10);
  EXPECT_DOUBLE_EQ(work.total, 25.5 + 26.5 + 15.5);

  // a priori: potential targets; a posteriori: 100 x cost / mean cost, rounded.
  EXPECT_EQ(vertex_weights(GraphModel::APriori, work.cost, w.potential, 1.0),
            (std::vector<std::int64_t>{1, 2, 1}));
  const double mean = work.total / 3;
  EXPECT_EQ(
      vertex_weights(GraphModel::APosteriori, work.cost, w.potential, mean),
      (std::vector<std::int64_t>{std::llround(100 * 25.5 / mean), std::llround(100 * 26.5 / mean),
                                 std::llround(100 * 15.5 / mean)}));
  // A contact edge weighs 1 + a contact in pair checks (a posteriori); every edge 1 a priori.
  EXPECT_EQ(edge_weights(GraphModel::APosteriori, c).of(true), 21);
  EXPECT_EQ(edge_weights(GraphModel::APosteriori, c).of(false), 1);
  EXPECT_EQ(edge_weights(GraphModel::APriori, c).of(true), 1);
  c.pair_check = 0; // a fitted free pair check: the ratio is taken as 1
  EXPECT_EQ(edge_weights(GraphModel::APosteriori, c).of(true), 2);

  const TermCounts sums = w.term_sums(7);
  EXPECT_DOUBLE_EQ(sums[kParticle], 3);
  EXPECT_DOUBLE_EQ(sums[kWallCheck], 3);
  EXPECT_DOUBLE_EQ(sums[kPairCheck], 4);
  EXPECT_DOUBLE_EQ(sums[kSphereContact], 2);
  EXPECT_DOUBLE_EQ(sums[kWallContact], 1);
  EXPECT_DOUBLE_EQ(sums[kGhost], 7);
  EXPECT_DOUBLE_EQ(sums[kBridge], 0);
  // Halves of a pair's work add up to the pair's check and contact.
  EXPECT_DOUBLE_EQ(2 * half_pair_cost(c, true), c.pair_check + c.sphere_contact);
}

// A bridged particle pays its bridges on top of its checks and contacts; the bridge term sums.
TEST(CostModel, BridgesAreATermOfTheirOwn)
{
  InteractionCosts c;
  c.particle = 4, c.pair_check = 1, c.sphere_contact = 20, c.bridge = 6;
  WorkCounts w;
  w.reset(2, 0);
  w.potential = {3, 3};
  w.contacts = {1, 1};
  w.bridges = {2, 0};
  const RankWork work = price_counts(c, w);
  EXPECT_DOUBLE_EQ(work.cost[0], 4 + 3 + 20 + 2 * 6);
  EXPECT_DOUBLE_EQ(work.cost[1], 4 + 3 + 20);
  EXPECT_DOUBLE_EQ(particle_cost(c, w.particle(0)), work.cost[0]);
  EXPECT_DOUBLE_EQ(w.term_sums(0)[kBridge], 2);
}

TEST(CostModel, TimedSplitsTheMeasuredTimeAndStartCheckUsesTheModel)
{
  const WorkCounts w = three_particles();
  const CostPricing timed(CostModel::Timed, unit_costs());
  const RankWork model = price_counts(unit_costs(), w);
  const RankWork start = timed.price(w, true, 2.0, 10);
  EXPECT_EQ(start.cost, model.cost);
  const RankWork measured = timed.price(w, false, 2.0, 10);
  EXPECT_DOUBLE_EQ(measured.total, 2.0);
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(measured.cost[i], 2.0 * model.cost[i] / model.total, 1e-15);
  const CostPricing counts(CostModel::Counts, unit_costs());
  EXPECT_EQ(counts.price(w, false, 2.0, 10).cost, model.cost);
  EXPECT_FALSE(counts.refits(false));
  EXPECT_FALSE(CostPricing(CostModel::Fitted, unit_costs()).refits(true));
}

// Samples whose time is the prior's model time x f: the fit gives f x the prior (the ridge pulls
// towards that same common factor); after kFitWindowChecks checks at a new factor the old
// samples are gone.
TEST(CostModel, FittedFollowsTheMeasuredTimeOverItsWindow)
{
  InteractionCosts prior;
  prior.particle = 5, prior.pair_check = 1, prior.sphere_contact = 20;
  CostPricing fitted(CostModel::Fitted, prior);
  const auto check = [&](double factor, int seed) {
    std::vector<double> per_rank;
    for (int r = 0; r < 3; ++r) {
      WorkCounts w;
      w.reset(10 + 7 * r + seed % 5, 0);
      for (int i = 0; i < w.size(); ++i)
        w.potential[i] = (i * (r + 2) + seed) % 9, w.contacts[i] = (i + r + seed) % 4;
      const TermCounts sums = w.term_sums(0);
      per_rank.insert(per_rank.end(), sums.begin(), sums.end());
      per_rank.push_back(factor * price_counts(prior, w).total * 20); // seconds of 20 steps
    }
    fitted.refit(per_rank, 20);
  };
  for (int k = 0; k < kFitWindowChecks; ++k)
    check(2.0, k);
  EXPECT_TRUE(fitted.has_fit());
  EXPECT_NEAR(fitted.costs().pair_check, 2.0, 1e-9);
  EXPECT_NEAR(fitted.costs().sphere_contact, 40.0, 1e-8);
  EXPECT_NEAR(fitted.costs().particle, 10.0, 1e-8);
  for (int k = 0; k < kFitWindowChecks; ++k)
    check(3.0, k + 11);
  EXPECT_NEAR(fitted.costs().pair_check, 3.0, 1e-9);
  // Particle costs per interval: the fitted per-step costs x the interval's steps.
  const WorkCounts w = three_particles();
  const RankWork work = fitted.price(w, false, 0.0, 20);
  EXPECT_NEAR(work.cost[0], 20 * particle_cost(fitted.costs(), w.particle(0)), 1e-9);
  EXPECT_THROW(fitted.refit({1.0, 2.0}, 20), std::invalid_argument);
}

// A restart carries the prior, the costs and the fit's window: the restored pricing prices alike
// and refits alike (the next refit drops the same oldest samples).
TEST(CostModel, RestoredPricingContinuesTheFit)
{
  InteractionCosts prior;
  prior.particle = 5, prior.pair_check = 1, prior.sphere_contact = 20;
  CostPricing fitted(CostModel::Fitted, prior);
  const auto sample = [](double factor, int seed) {
    std::vector<double> per_rank;
    for (int r = 0; r < 2; ++r) {
      WorkCounts w;
      w.reset(8 + 5 * r + seed % 3, 0);
      for (int i = 0; i < w.size(); ++i)
        w.potential[i] = (i * (r + 3) + seed) % 7, w.contacts[i] = (i + r + seed) % 3;
      const TermCounts sums = w.term_sums(0);
      per_rank.insert(per_rank.end(), sums.begin(), sums.end());
      per_rank.push_back(factor * (1 + 0.1 * ((seed + r) % 4)) * sums[0]);
    }
    return per_rank;
  };
  for (int k = 0; k < kFitWindowChecks; ++k)
    fitted.refit(sample(1.5, k), 10);
  CostPricing restored(CostModel::Fitted, unit_costs()); // the start-up prior, replaced
  restored.restore(fitted.state());
  EXPECT_EQ(restored.state(), fitted.state());
  EXPECT_TRUE(restored.has_fit());
  const WorkCounts w = three_particles();
  EXPECT_EQ(restored.price(w, false, 0.0, 10).cost, fitted.price(w, false, 0.0, 10).cost);
  fitted.refit(sample(2.5, 17), 10);
  restored.refit(sample(2.5, 17), 10);
  EXPECT_EQ(restored.state(), fitted.state());
  EXPECT_NE(restored.costs().pair_check, CostPricing(CostModel::Fitted, prior).costs().pair_check);
  EXPECT_THROW(restored.restore(std::vector<double>(2 * kCostTerms + 1, 1.0)),
               std::invalid_argument);
}

// The restart state reads back as written (outputs, schedule, grid, owners, costs), and a file of
// the older format (the outputs' six numbers) reads as incomplete with its outputs.
TEST(BalanceRestart, PacksAndReadsBack)
{
  BalanceRestart r;
  r.outputs.imbalance = 1.25, r.outputs.predicted_imbalance = 1.01, r.outputs.repartitions = 3;
  r.outputs.edge_cut = 417, r.outputs.checks = 9, r.outputs.measured_imbalance = 1.5;
  r.nranks = 3, r.last_check = 140;
  const double lo[3] = {0, 0, -1}, hi[3] = {1, 2, 1};
  const bool periodic[3] = {true, false, false};
  r.grid = make_cell_grid(lo, hi, 0.25, 3, periodic);
  for (int64_t c = 0; c < r.grid.total(); ++c)
    r.cell_owners.push_back(static_cast<int>(c % 3));
  r.pricing = {1, 2, 3, 4.5};
  const std::vector<double> packed = pack_balance_restart(r);
  EXPECT_EQ(packed[0], -static_cast<double>(packed.size()));
  const BalanceRestart back = unpack_balance_restart(packed.data());
  EXPECT_TRUE(back.complete);
  EXPECT_EQ(pack_balance_restart(back), packed);
  EXPECT_EQ(back.cell_owners, r.cell_owners);
  EXPECT_EQ(back.grid.total(), r.grid.total());
  EXPECT_TRUE(back.grid.periodic[0] && !back.grid.periodic[1]);
  EXPECT_EQ(back.last_check, 140);
  EXPECT_EQ(back.outputs.predicted_imbalance, 1.01);

  double old[BalanceOutputs::kRestartSize];
  r.outputs.save(old);
  const BalanceRestart legacy = unpack_balance_restart(old);
  EXPECT_FALSE(legacy.complete);
  EXPECT_EQ(legacy.outputs.repartitions, 3);
  EXPECT_EQ(legacy.outputs.edge_cut, 417);

  std::vector<double> bad = packed;
  bad[0] = -20; // a count that the contents overrun
  EXPECT_THROW(unpack_balance_restart(bad.data()), std::invalid_argument);
}

TEST(BalanceCheck, TriggerFiresExactlyAboveTheThreshold)
{
  const ImbalanceTrigger t{1.1};
  EXPECT_FALSE(t.fires(1.1, 4));
  EXPECT_FALSE(t.fires(1.05, 4));
  EXPECT_TRUE(t.fires(std::nextafter(1.1, 2.0), 4));
  EXPECT_FALSE(t.fires(3.0, 1)); // one rank: nothing to balance
  // B of per-rank work 3, 1, 2: max 3 over average 2.
  const RankSpread s = rank_spread({3.0, 1.0, 2.0});
  EXPECT_DOUBLE_EQ(s.imbalance, 1.5);
  EXPECT_TRUE(ImbalanceTrigger{1.49}.fires(s.imbalance, 3));
  EXPECT_FALSE(ImbalanceTrigger{1.5}.fires(s.imbalance, 3));
  EXPECT_DOUBLE_EQ(rank_spread({0.0, 0.0}).imbalance, 1.0);
  EXPECT_THROW(rank_spread(std::vector<double>{}), std::invalid_argument);
}

TEST(BalanceCheck, ScheduleStartsBalancedThenChecksAtMultiples)
{
  CheckSchedule s(10);
  s.setup(0, true);
  EXPECT_EQ(s.next(), 1);
  EXPECT_FALSE(s.due(0));
  const CheckSchedule::Check first = s.take(1);
  EXPECT_TRUE(first.start);
  EXPECT_DOUBLE_EQ(first.interval_steps, 1);
  EXPECT_EQ(s.next(), 10);
  const CheckSchedule::Check second = s.take(10);
  EXPECT_FALSE(second.start);
  EXPECT_DOUBLE_EQ(second.interval_steps, 9);
  s.setup(25, false); // a second run: no start check
  EXPECT_EQ(s.next(), 30);
  CheckSchedule late(10);
  late.setup(9, true); // the first regular check comes first
  EXPECT_EQ(late.next(), 10);
  EXPECT_THROW(CheckSchedule(0), std::invalid_argument);
}

TEST(BalanceReport, RowHoldsThePerRankWorkAsComputedByHand)
{
  CheckRow row;
  row.step = 40;
  row.repartitioned = true;
  row.predicted_imbalance = 1.01, row.migrated = 12, row.edge_cut = 33, row.natoms = 500;
  row.work = rank_spread({30.0, 10.0, 20.0});
  row.cpu_per_rank = {0.5, 0.25, 0.25};
  row.cpu = rank_spread(row.cpu_per_rank);
  row.ghosts = rank_spread({40.0, 20.0, 30.0});
  const std::vector<std::string> head = csv_fields(report_header(3));
  const std::vector<std::string> f = csv_fields(report_row(row));
  ASSERT_EQ(head.size(), 19u);
  ASSERT_EQ(f.size(), head.size());
  const auto at = [&](const std::string& name) {
    for (std::size_t k = 0; k < head.size(); ++k)
      if (head[k] == name) return std::stod(f[k]);
    ADD_FAILURE() << "no column " << name;
    return 0.0;
  };
  EXPECT_DOUBLE_EQ(at("step"), 40);
  EXPECT_DOUBLE_EQ(at("imbalance"), 1.5); // 30 / 20
  EXPECT_DOUBLE_EQ(at("repartitioned"), 1);
  EXPECT_DOUBLE_EQ(at("work_max"), 30);
  EXPECT_DOUBLE_EQ(at("work_avg"), 20);
  EXPECT_NEAR(at("ghost_max_over_avg"), 40.0 / 30.0, 1e-5); // 6 significant digits
  EXPECT_DOUBLE_EQ(at("ghosts_total"), 90);
  EXPECT_DOUBLE_EQ(at("measured_imbalance"), 1.5);
  EXPECT_DOUBLE_EQ(at("cpu_work_max"), 0.5);
  EXPECT_DOUBLE_EQ(at("cpu_rank1"), 0.25);
  EXPECT_DOUBLE_EQ(at("migrated"), 12);
  EXPECT_DOUBLE_EQ(at("natoms"), 500);
  EXPECT_EQ(head.back(), "cpu_rank2");
}

TEST(BalanceReport, OutputsVectorAndRestartRoundTrip)
{
  BalanceOutputs o;
  o.record_check(rank_spread({3.0, 1.0}), rank_spread({1.0, 1.0}), rank_spread({4.0, 2.0}));
  o.record_repartition(1.02, 17, 40);
  EXPECT_DOUBLE_EQ(o.vector(0, 0), 1.5); // B before the repartition
  EXPECT_DOUBLE_EQ(o.vector(1, 0), 1);
  EXPECT_DOUBLE_EQ(o.vector(2, 0), 40);
  EXPECT_DOUBLE_EQ(o.vector(3, 0.25), 0.25); // partition + migration seconds
  EXPECT_DOUBLE_EQ(o.vector(4, 0), 4.0 / 3.0);
  EXPECT_DOUBLE_EQ(o.vector(5, 0), 17);
  EXPECT_DOUBLE_EQ(o.vector(6, 0), 1);
  EXPECT_DOUBLE_EQ(o.vector(7, 0), 1.02);
  EXPECT_DOUBLE_EQ(o.vector(8, 0), 6);
  EXPECT_DOUBLE_EQ(o.vector(9, 0), 1);
  EXPECT_DOUBLE_EQ(o.vector(10, 0), 0);
  double state[BalanceOutputs::kRestartSize];
  o.save(state);
  BalanceOutputs back;
  back.load(state);
  for (int n = 0; n < BalanceOutputs::kVectorSize; ++n)
    if (n != 4 && n != 7 && n != 8 && n != 9) EXPECT_DOUBLE_EQ(back.vector(n, 0), o.vector(n, 0));
}

// Rank 0 holds particles 5 and 7, rank 1 particle 2; an edge to particle 9 (no vertex) is dropped.
TEST(GatheredGraph, ParticleAndCellGraphsFromRankShares)
{
  GatheredGraph gg;
  gg.verts = {5, 3, 7, 1, 2, 4};
  gg.edges = {5, 2, 2, 7, 9, 1};
  gg.vcount = {4, 2}, gg.vdisp = {0, 4}, gg.vtotal = 6, gg.etotal = 6;
  const RootGraph rg = particle_graph(gg, 2);
  EXPECT_EQ(rg.g.num_vertices(), 3);
  EXPECT_EQ(rg.g.num_edges(), 1);
  // Vertices in tag order (2, 5, 7); the gathered entries (5, 7, 2) map back to them.
  EXPECT_EQ(rg.g.vwgt, (std::vector<std::int64_t>{4, 3, 1}));
  EXPECT_EQ(rg.old_owner, (std::vector<int>{1, 0, 0}));
  EXPECT_EQ(parts_of_entries(rg, {20, 50, 70}), (std::vector<int>{50, 70, 20}));

  // Cells: particles of weight 2, 3, 5 in cells 0, 0, 3; their edges sum per cell pair.
  const LocalGraph lg = aggregate_cells({2, 3, 5}, {0, 0, 3}, {0, 3, 4, 3, 0, 1}, 4);
  std::int64_t weight0 = 0, weight3 = 0;
  for (std::size_t k = 0; k < lg.verts.size(); k += 2)
    (lg.verts[k] == 0 ? weight0 : weight3) += lg.verts[k + 1];
  EXPECT_EQ(weight0, 5);
  EXPECT_EQ(weight3, 5);
  EXPECT_EQ(lg.edges, (std::vector<std::int64_t>{0, 3, 5}));
}
