#include "core/lawson.hpp"

#include "core/predicates.hpp"
#include "core/schedule.hpp"
#include "util/chunked_sum.hpp"
#include "util/error.hpp"
#include "util/prefaulted_image.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cstdint>
#include <limits>

namespace ddt::core {
namespace {

// Simplices of a cell with 2 .. D vertices: 2^(D+1) subsets minus the empty
// one, the D + 1 vertices and the cell.
template <int D>
inline constexpr int items_per_cell = (1 << (D + 1)) - (D + 1) - 2;

// Local vertex masks of the items: facet j first (every vertex but j), then
// by decreasing size, then by mask.
template <int D>
std::array<unsigned, items_per_cell<D>> make_item_masks() {
  std::array<unsigned, items_per_cell<D>> masks{};
  const unsigned all = (1u << (D + 1)) - 1;
  int n = 0;
  for (int j = 0; j <= D; ++j) masks[n++] = all & ~(1u << j);
  for (int size = D - 1; size >= 2; --size)
    for (unsigned m = 0; m <= all; ++m)
      if (std::popcount(m) == size) masks[n++] = m;
  return masks;
}

template <int D>
const std::array<unsigned, items_per_cell<D>> item_masks = make_item_masks<D>();

// What one band (or the single region) does in a phase.
struct RegionRun {
  std::int32_t region = 0;
  std::vector<index_t> cells;   // phase 0: the cells whose initial items it scans, in order
  std::vector<index_t> items;   // later phases: the items handed to it
  std::vector<index_t> pool;    // slots for new cells
  std::vector<index_t> deferred;
  FlipCounts flips;  // dimension set by the first +=
  long long tests = 0, deferred_tests = 0;
  double gains = 0;  // in the order of the flips
  int iterations = 0;
  double work = 0;  // an estimate of the phase's work: the largest regions start first
};

// The distinct keys of one flip's lower simplices, in the order first
// inserted: open addressing over at most Capacity keys (a scan of the keys
// seen grew with their square, a quarter of a 4D optimization's time).
template <class Key, int Capacity>
class KeySet {
 public:
  explicit KeySet(int expected) {
    const std::size_t wanted = 2 * static_cast<std::size_t>(std::max(0, expected));  // at most half full
    while (mask_ + 1 < wanted && mask_ + 1 < table_size) mask_ = 2 * mask_ + 1;
    std::fill(slots_.begin(), slots_.begin() + mask_ + 1, std::uint16_t(0));
  }
  // False when the key was inserted before.
  bool insert(const Key& key) {
    std::uint64_t h = 0x9e3779b97f4a7c15ull;
    for (const auto id : key) h = (h ^ static_cast<std::uint32_t>(id)) * 0xff51afd7ed558ccdull;
    for (std::size_t slot = (h >> 40) & mask_;; slot = (slot + 1) & mask_) {
      const std::uint16_t held = slots_[slot];
      if (held == 0) {
        keys_[count_] = key;
        slots_[slot] = static_cast<std::uint16_t>(++count_);
        return true;
      }
      if (same_ids(keys_[held - 1], key)) return false;
    }
  }

 private:
  static constexpr std::size_t table_size = std::bit_ceil(2u * Capacity);
  static_assert(Capacity < 65535, "slots hold 16-bit indices");
  std::array<Key, Capacity> keys_;
  std::array<std::uint16_t, table_size> slots_;
  std::size_t mask_ = 15;
  int count_ = 0;
};

template <int D>
class Optimizer {
 public:
  static constexpr int P = items_per_cell<D>;

  Optimizer(SimplexMesh<D>& mesh, const std::vector<float>& values, int K, const CostFunction& cost,
            const LawsonOptions& options)
      : mesh_(mesh), z_(values.data()), K_(K), cost_(cost), options_(options),
        facet_(cost.form != CostForm::simplex_weight), lattice_(lattice_exact<D>(mesh.points)) {}

  // The first List_active as a mask per cell (bit j: item P c + j): each
  // facet from its smaller slot, each lower simplex from the smallest slot
  // of its star (when the star is small enough to flip).
  std::vector<std::uint32_t> initial_items() const {
    const index_t n = mesh_.slot_count();
    std::vector<std::uint32_t> mask = prefaulted_zeros<std::uint32_t>(n);
    tbb::parallel_for(index_t(0), n, [&](index_t c) {
      if (!mesh_.is_live(c)) return;
      std::uint32_t m = 0;
      for (int i = 0; i <= D; ++i) {
        const index_t g = mesh_.opp[(D + 1) * c + i];
        if (g != no_facet && cell_of<D>(g) > c) m |= 1u << i;
      }
      for (int j = D + 1; j < P; ++j)
        if (first_of_star<D>(mesh_, c, item_masks<D>[j])) m |= 1u << j;
      mask[c] = m;
    });
    return mask;
  }

  // Lawson's loop over one region's items; scope null: the whole mesh.
  // on_iteration(iteration, flips in it) after each iteration.
  template <class OnIteration>
  void run_region(RegionRun& run, const std::vector<std::uint32_t>* initial, const ReadScope* scope,
                  OnIteration on_iteration) {
    std::vector<index_t> candidate;
    auto touch = [&](index_t item) {
      if (scope && !scope->reads(item / P)) {
        run.deferred.push_back(item);
        return;
      }
      if (static_cast<std::size_t>(item) >= pending_.size()) pending_.resize(static_cast<std::size_t>(P) * mesh_.slot_count(), 0);
      if (pending_[item]) return;
      pending_[item] = 1;
      candidate.push_back(item);
    };
    auto test = [&](index_t item, FlipCounts& flips_now) {
      pending_[item] = 0;
      ++run.tests;
      run.gains += improve(item, scope, run, flips_now, touch);
    };
    auto scan_initial = [&](FlipCounts& now) {
      for (index_t c : run.cells)
        for (std::uint32_t m = (*initial)[c]; m; m &= m - 1) test(P * c + std::countr_zero(m), now);
    };
    lawson_iterations(
        initial != nullptr, std::move(run.items), candidate, options_.max_iterations, run.iterations, run.flips,
        [] {
          FlipCounts f;
          f.dimension = D;
          return f;
        },
        scan_initial, test, [&](index_t item) { pending_[item] = 0; }, on_iteration);
  }

  // How far the values of cell c spread (summed over the channels): flat
  // cells rarely flip, so a region's sum estimates its first phase's work.
  double spread(index_t c) const {
    double sum = 0;
    for (int ch = 0; ch < K_; ++ch) {
      float lo = z_[static_cast<std::size_t>(mesh_.vertex(c, 0)) * K_ + ch], hi = lo;
      for (int i = 1; i <= D; ++i) {
        const float v = z_[static_cast<std::size_t>(mesh_.vertex(c, i)) * K_ + ch];
        lo = std::min(lo, v), hi = std::max(hi, v);
      }
      const double d = double(hi) - double(lo);
      if (d < std::numeric_limits<double>::infinity()) sum += d;  // not NaN or inf: the order sorts on it
    }
    return sum;
  }

  // total_cost; for simplex-weight costs the same sum of the kept terms.
  double total() const {
    if (facet_) return total_cost<D>(mesh_, z_, K_, cost_);
    return chunked_sum(mesh_.slot_count(),
                       [&](index_t c) { return mesh_.is_live(c) ? cell_costs_[c] : 0.0; });
  }

  // Simplex-weight costs: each live cell's term, kept per slot so a test
  // computes only the cells a flip would insert.
  void init_cell_costs() {
    if (facet_) return;
    cell_costs_ = prefaulted_zeros<double>(mesh_.slot_count(), lawson_pool_room(mesh_.slot_count()));
    tbb::parallel_for(index_t(0), mesh_.slot_count(), [&](index_t c) {
      if (mesh_.is_live(c)) cell_costs_[c] = cell_cost<D>(mesh_, z_, K_, cost_, mesh_.cell_vertices(c));
    });
  }
  // Room for slots appended before a parallel phase.
  void reserve_cell_costs() {
    if (!facet_) prefaulted_resize(cell_costs_, static_cast<std::size_t>(mesh_.slot_count()), 0.0);
  }

  // Flags the items of the first List_active as pending.
  void set_pending(const std::vector<std::uint32_t>& initial) {
    pending_ = prefaulted_zeros<char>(static_cast<std::size_t>(P) * mesh_.slot_count());
    tbb::parallel_for(index_t(0), static_cast<index_t>(initial.size()), [&](index_t c) {
      for (std::uint32_t m = initial[c]; m; m &= m - 1) pending_[P * c + std::countr_zero(m)] = 1;
    });
  }

  std::vector<char> pending_;        // per item: on a list, not yet tested
  std::vector<std::int32_t> owner_;  // per slot: the band owning it this phase
  std::vector<double> cell_costs_;   // per slot (simplex-weight costs only)

 private:
  // Tests one item; applies the best improving flip (counted in flips)
  // and returns its gain, else 0. Defers the item (run.deferred) when its flip reaches outside
  // the scope or needs more slots than the pool holds.
  template <class Touch>
  double improve(index_t item, const ReadScope* scope, RegionRun& run, FlipCounts& flips, Touch touch) {
    const index_t c = item / P;
    if (!mesh_.is_live(c)) return 0;
    FlipPlan<D> plans[2];
    const int n = propose_flip<D>(mesh_, c, item_masks<D>[item % P], plans, 2, {scope, lattice_});
    auto defer = [&] {
      run.deferred.push_back(item);
      ++run.deferred_tests;
      return 0.0;
    };
    if (n < 0) return defer();
    if (n == 0) return 0;
    if (scope)  // the flip rewrites the links of the cells around it, and facet costs read them
      for (int k = 0; k < plans[0].removed_count; ++k)
        for (int i = 0; i <= D; ++i) {
          const index_t g = mesh_.opp[(D + 1) * plans[0].removed[k] + i];
          if (g != no_facet && !scope->reads(cell_of<D>(g))) return defer();
        }
    // A simplex weight depends only on the vertex values: where they are
    // all equal every cell has the same weight and the content is kept.
    if (!facet_ && uniform_values(plans[0])) return 0;
    double gains[2] = {0, 0};
    int best = -1;
    std::array<double, max_flip_cells<D>> removed_costs, inserted_costs[2];
    if (!facet_)
      for (int k = 0; k < plans[0].removed_count; ++k) removed_costs[k] = cell_costs_[plans[0].removed[k]];
    for (int p = 0; p < n; ++p) {
      if (options_.kept_simplex && options_.kept_simplex(plans[p].a.data(), plans[p].a_count)) continue;
      const LocalCosts lc = facet_ ? flip_costs<D>(mesh_, z_, K_, cost_, plans[p])
                                   : flip_costs<D>(mesh_, z_, K_, cost_, plans[p], removed_costs.data(),
                                                   inserted_costs[p].data());
      if (!lc.improves(options_.relative_tolerance)) continue;
      gains[p] = lc.gain();
      if (best < 0 || gains[p] > gains[best]) best = p;
    }
    if (best < 0) return 0;
    const FlipPlan<D>& plan = plans[best];
    const int needed = plan.inserted_count - plan.removed_count;
    if (scope && needed > static_cast<int>(run.pool.size())) return defer();
    std::array<index_t, max_flip_cells<D>> slots;
    apply_flip<D>(mesh_, plan, slots.data(), scope ? &run.pool : nullptr);
    if (!facet_) {
      if (cell_costs_.size() < static_cast<std::size_t>(mesh_.slot_count())) cell_costs_.resize(mesh_.slot_count());  // one region only
      for (int k = 0; k < plan.inserted_count; ++k) cell_costs_[slots[k]] = inserted_costs[best][k];
    }
    flips.add(plan.removed_count, plan.inserted_count);
    touch_around(slots.data(), plan, touch);
    return gains[best];
  }

  bool uniform_values(const FlipPlan<D>& plan) const {
    const float* first = z_ + static_cast<std::size_t>(mesh_.vertex(plan.removed[0], 0)) * K_;
    for (int k = 0; k < plan.removed_count; ++k)
      for (int i = 0; i <= D; ++i) {
        const float* v = z_ + static_cast<std::size_t>(mesh_.vertex(plan.removed[k], i)) * K_;
        for (int c = 0; c < K_; ++c)
          if (v[c] != first[c]) return false;
      }
    return true;
  }

  // The items of the new cells, and for facet costs of their neighbours;
  // a facet from its smaller slot, a lower simplex once per flip. In 2D
  // and 3D not the simplices that contain conv B: every cell around them
  // is new, and each flip removing one restores the old cells (a raise by
  // the gain just taken) or gives the other plan the flip was chosen
  // against, so they are locally optimal now; a later flip that changes
  // that lists them. (4D's degenerate stars can offer more than the two
  // plans compared, so there they are listed.)
  template <class Touch>
  void touch_around(const index_t* slots, const FlipPlan<D>& plan, Touch touch) const {
    const int count = plan.inserted_count;
    constexpr int cap = max_flip_cells<D> * (D + 2);
    std::array<index_t, cap> cells;
    int n_cells = 0;
    for (int k = 0; k < count; ++k) cells[n_cells++] = slots[k];
    if (facet_)
      for (int k = 0; k < count; ++k)
        for (int i = 0; i <= D; ++i) {
          const index_t g = mesh_.opp[(D + 1) * slots[k] + i];
          if (g == no_facet) continue;
          const index_t u = cell_of<D>(g);
          if (std::find(cells.begin(), cells.begin() + n_cells, u) == cells.begin() + n_cells) cells[n_cells++] = u;
        }
    // Per cell, the local vertices holding B (all B's vertices are in a new cell).
    auto b_mask = [&](index_t c) {
      unsigned m = 0;
      int found = 0;
      for (int i = 0; i <= D; ++i)
        for (int j = 0; j < plan.b_count; ++j)
          if (mesh_.vertex(c, i) == plan.b[j]) m |= 1u << i, ++found;
      return D <= 3 && found == plan.b_count ? m : ~0u;  // ~0u: no simplex of c is skipped
    };
    using Key = std::array<index_t, D>;
    // 3D keys its lower simplices, the edges, in one word each (below).
    KeySet<Key, cap*(P - D - 1 > 0 ? P - D - 1 : 1)> seen_keys(D == 3 ? 0 : n_cells * (P - D - 1));
    std::array<std::uint64_t, D == 3 ? cap * (P - D - 1) : 1> seen_edges;
    int n_seen = 0;
    for (int j = 0; j < n_cells; ++j) {
      const index_t c = cells[j];
      const unsigned holds_b = b_mask(c);
      for (int i = 0; i <= D; ++i) {
        const index_t g = mesh_.opp[(D + 1) * c + i];
        if (g == no_facet || (holds_b & item_masks<D>[i]) == holds_b) continue;
        touch(cell_of<D>(g) < c ? P * cell_of<D>(g) + local_of<D>(g) : P * c + i);
      }
      for (int m = D + 1; m < P; ++m) {
        if ((holds_b & item_masks<D>[m]) == holds_b) continue;
        if constexpr (D == 3) {  // the lower simplices are edges: a key of two ids in one word
          const unsigned mask = item_masks<D>[m];
          const index_t u = mesh_.vertex(c, std::countr_zero(mask)), v = mesh_.vertex(c, 31 - std::countl_zero(mask));
          const std::uint64_t key = std::uint64_t(std::uint32_t(std::min(u, v))) << 32 | std::uint32_t(std::max(u, v));
          if (std::find(seen_edges.begin(), seen_edges.begin() + n_seen, key) != seen_edges.begin() + n_seen) continue;
          seen_edges[n_seen++] = key;
          touch(P * c + m);
          continue;
        }
        Key key;  // the simplex's vertex ids, then sentinels (sorted last)
        key.fill(std::numeric_limits<index_t>::max());
        for (int i = 0, n = 0; i <= D; ++i)
          if (item_masks<D>[m] & (1u << i)) key[n++] = mesh_.vertex(c, i);
        std::sort(key.begin(), key.end());
        if (!seen_keys.insert(key)) continue;
        touch(P * c + m);
      }
    }
  }

  SimplexMesh<D>& mesh_;
  const float* z_;
  int K_;
  const CostFunction& cost_;
  const LawsonOptions& options_;
  bool facet_;
  bool lattice_;  // lattice_exact(mesh.points): plain orientations
};

// The band of vertex v in a phase whose bands are shifted by `shift`.
std::int32_t band_of(index_t v, long long size, long long shift) {
  return static_cast<std::int32_t>((v + shift) / size);
}

template <int D>
void run_phases(Optimizer<D>& opt, SimplexMesh<D>& mesh, long long size, const LawsonOptions& options,
                LawsonStats& stats) {
  constexpr int P = Optimizer<D>::P;
  const std::vector<std::uint32_t> initial = opt.initial_items();
  const long long V = static_cast<long long>(mesh.points.size());
  double cost_now = stats.cost_before;
  std::vector<index_t> list;  // items handed to the next phase, in a fixed order
  auto no_report = [](int, const FlipCounts&) {};
  auto run_phase = [&](int phase, bool single) {
    FlipCounts flips_now;
    flips_now.dimension = D;
    if (single) {
      RegionRun run;
      run.items = std::move(list);
      list.clear();
      opt.run_region(run, nullptr, nullptr, no_report);
      flips_now = run.flips;
      stats.tests += run.tests;
      cost_now -= run.gains;
    } else {
      const long long shift = phase % 2 == 1 ? size / 2 : 0;
      const std::int32_t regions = band_of(static_cast<index_t>(V - 1), size, shift) + 1;
      if (phase == 0) stats.regions = regions;
      std::vector<RegionRun> runs(regions);
      // The fresh slots are appended at once, into pages mapped in one call
      // (faulting them in one by one was most of phase 0's set-up:
      // docs/volumes.md), numbered in the same order as one by one.
      const index_t reserve = static_cast<index_t>(std::max<long long>(256, mesh.cell_count() / regions / pool_share));
      const std::size_t wanted = static_cast<std::size_t>(regions) * reserve;
      const std::size_t fresh = wanted > mesh.free_slots.size() ? wanted - mesh.free_slots.size() : 0;
      index_t next_fresh = mesh.slot_count();
      prefaulted_resize(mesh.cell, mesh.cell.size() + fresh * (D + 1), no_vertex);
      prefaulted_resize(mesh.opp, mesh.opp.size() + fresh * (D + 1), no_facet);
      opt.owner_.clear();
      prefaulted_resize(opt.owner_, static_cast<std::size_t>(mesh.slot_count()), std::int32_t(-1));
      tbb::parallel_for(index_t(0), mesh.slot_count(), [&](index_t c) {
        if (!mesh.is_live(c)) return;
        index_t low = mesh.vertex(c, 0);
        for (int i = 1; i <= D; ++i) low = std::min(low, mesh.vertex(c, i));
        opt.owner_[c] = band_of(low, size, shift);
      });
      // Pools: free slots first, then fresh ones (lawson.hpp's pool_share).
      for (std::int32_t r = 0; r < regions; ++r) {
        runs[r].region = r;
        for (index_t k = 0; k < reserve; ++k) {
          index_t slot;
          if (!mesh.free_slots.empty()) {
            slot = mesh.free_slots.back();
            mesh.free_slots.pop_back();
          } else {
            slot = next_fresh++;
          }
          opt.owner_[slot] = r;
          runs[r].pool.push_back(slot);
        }
        std::reverse(runs[r].pool.begin(), runs[r].pool.end());  // the lowest slot is taken first
      }
      opt.reserve_cell_costs();
      if (phase == 0) opt.set_pending(initial);
      prefaulted_resize(opt.pending_, static_cast<std::size_t>(P) * mesh.slot_count(), char(0));
      if (phase == 0) {
        for (index_t c = 0; c < static_cast<index_t>(initial.size()); ++c)
          if (initial[c]) {
            RegionRun& run = runs[opt.owner_[c]];
            run.cells.push_back(c);
            run.work += opt.spread(c);
          }
      } else {
        for (index_t item : list) {
          const std::int32_t r = opt.owner_[item / P];
          if (r >= 0) runs[r].items.push_back(item);
          else opt.pending_[item] = 0;  // its cell was removed
        }
        list.clear();
        for (RegionRun& run : runs) run.work = static_cast<double>(run.items.size());
      }
      // Regions are independent within a phase, so the order they run in
      // changes no result. Largest first (by the estimate), each thread
      // taking the next: on smooth data the work gathers in a few regions,
      // and in index order one of them was left running alone at the end.
      std::vector<std::int32_t> order(regions);
      for (std::int32_t r = 0; r < regions; ++r) order[r] = r;
      std::stable_sort(order.begin(), order.end(),
                       [&](std::int32_t a, std::int32_t b) { return runs[a].work > runs[b].work; });
      std::atomic<std::int32_t> next{0};
      tbb::parallel_for(
          std::int32_t(0), regions,
          [&](std::int32_t) {
            for (std::int32_t k; (k = next.fetch_add(1)) < regions;) {
              const ReadScope scope{opt.owner_.data(), order[k]};
              opt.run_region(runs[order[k]], phase == 0 ? &initial : nullptr, &scope, no_report);
            }
          },
          tbb::simple_partitioner());
      for (RegionRun& run : runs) {
        flips_now += run.flips;
        stats.tests += run.tests;
        stats.deferred += run.deferred_tests;
        cost_now -= run.gains;
        for (index_t item : run.deferred) {
          if (opt.pending_[item]) continue;
          opt.pending_[item] = 1;
          list.push_back(item);
        }
        mesh.free_slots.insert(mesh.free_slots.end(), run.pool.rbegin(), run.pool.rend());
      }
    }
    stats.flips += flips_now;
    stats.iterations = phase + 1;
    if (options.on_iteration) options.on_iteration(phase + 1, flips_now, cost_now);
    return flips_now.total();
  };
  run_region_phases(options.max_iterations, run_phase, [&] { return !list.empty(); });
}

}  // namespace

long long FlipCounts::total() const {
  long long sum = 0;
  for (long long n : by_kind) sum += n;
  return sum;
}

FlipCounts& FlipCounts::operator+=(const FlipCounts& other) {
  dimension = std::max(dimension, other.dimension);
  for (std::size_t k = 0; k < by_kind.size(); ++k) by_kind[k] += other.by_kind[k];
  return *this;
}

std::string FlipCounts::summary() const {
  std::vector<std::pair<int, int>> kinds;
  for (int b = 2; b <= dimension; ++b) kinds.emplace_back(b, dimension + 2 - b);
  if (dimension == 3) kinds.insert(kinds.end(), {{4, 4}, {2, 2}});
  for (int removed = 0; removed < side; ++removed)
    for (int inserted = 0; inserted < side; ++inserted)
      if (count(removed, inserted) && std::find(kinds.begin(), kinds.end(), std::pair{removed, inserted}) == kinds.end())
        kinds.emplace_back(removed, inserted);
  std::string s;
  for (const auto& [removed, inserted] : kinds) {
    if (!s.empty()) s += ", ";
    s += std::to_string(removed) + "-" + std::to_string(inserted) + ": " + std::to_string(count(removed, inserted));
  }
  return s.empty() ? "none" : s;
}

template <int D>
LawsonStats optimize_lawson(SimplexMesh<D>& mesh, const std::vector<float>& values, int K, const CostFunction& cost,
                            const LawsonOptions& options) {
  if (K < 1 || K > max_cost_channels)
    throw Error("the cost takes 1 to " + std::to_string(max_cost_channels) + " channels, got " + std::to_string(K));
  if (values.size() != mesh.points.size() * static_cast<std::size_t>(K))
    throw Error("optimize_lawson: " + std::to_string(values.size()) + " values for " +
                std::to_string(mesh.points.size()) + " vertices and " + std::to_string(K) + " channels");
  Optimizer<D> opt(mesh, values, K, cost, options);
  opt.init_cell_costs();
  LawsonStats stats;
  stats.flips.dimension = D;
  stats.cost_before = opt.total();
  const long long cells = mesh.cell_count();
  const bool forced = options.region_vertices > 0;
  long long size = options.region_vertices;
  if (options.region_vertices == 0 && cells > 2 * default_region_cells)
    size = std::max<long long>(1, static_cast<long long>(mesh.points.size()) * default_region_cells / cells);
  if (forced || size > 0) {
    run_phases(opt, mesh, size, options, stats);
  } else {
    RegionRun run;
    run.cells.resize(mesh.slot_count());
    for (index_t c = 0; c < mesh.slot_count(); ++c) run.cells[c] = c;
    const std::vector<std::uint32_t> initial = opt.initial_items();
    opt.set_pending(initial);
    double cost_now = stats.cost_before;
    double reported_gains = 0;
    opt.run_region(run, &initial, nullptr, [&](int iteration, const FlipCounts& flips) {
      cost_now -= run.gains - reported_gains;
      reported_gains = run.gains;
      if (options.on_iteration) options.on_iteration(iteration, flips, cost_now);
    });
    stats.iterations = run.iterations;
    stats.flips += run.flips;
    stats.tests = run.tests;
  }
  stats.cost_after = opt.total();
  return stats;
}

template LawsonStats optimize_lawson<2>(SimplexMesh<2>&, const std::vector<float>&, int, const CostFunction&,
                                        const LawsonOptions&);
template LawsonStats optimize_lawson<3>(SimplexMesh<3>&, const std::vector<float>&, int, const CostFunction&,
                                        const LawsonOptions&);
template LawsonStats optimize_lawson<4>(SimplexMesh<4>&, const std::vector<float>&, int, const CostFunction&,
                                        const LawsonOptions&);

}  // namespace ddt::core
