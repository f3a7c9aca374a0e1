// Lattice and base-grid planning (see plan.h). The lattice is isotropic, so squared distances in
// lattice units are exact integers; base cells have a diagonal shorter than r (paper section 1).
#include "plan.h"

#include <cmath>
#include <fstream>
#include <sys/resource.h>
#include <unistd.h>

#include <fmt/format.h>

#include "shared/neighbourhood.h"
#include "shared/t_membership.h"

namespace vrpd::detail {
namespace {

constexpr std::uint32_t kLatticeLimit = 0x7FFFFFFFu;  // coordinates stay below 2^31 (grid tag bit)
constexpr std::uint32_t kMinCellBits = 10;            // >= 1024 lattice steps per base cell side

constexpr double kMaxCoverageRatio = 4.0;
// Below it T, the free points within Rc of U, is a thin crescent, and the darts, spread over
// whole base cells, take long to fill it, past the memory the plan assumes (docs/performance.md).
constexpr double kMinCoverageRatio = 1.1;
constexpr unsigned kMaxSteps = 1000;
constexpr double kMaxStart = 1024;
constexpr unsigned kMaxThreads = 1024;  // a host thread each: far above any machine's cores, below its limits

bool finite_positive(double v) { return std::isfinite(v) && v > 0.0; }

// A hierarchy's coarsest grid groups 2^J x 2^J base cells: the largest power of two <= S.
std::uint32_t hierarchy_levels(const SampleOptions& o) {
    if (o.hierarchy.steps == 0) return 0;
    return std::uint32_t(std::floor(std::log2(hierarchy_start(o)) + 1e-9));
}

// Squared lattice distances in the domain are < 2^63 (coordinates < 2^31), so a radius whose
// square reaches 2^63 covers the whole box: clamping it there is exact, and sums cannot wrap.
std::uint64_t squared_units(double radius, double quantum) {
    const long double rq = (long double)radius / (long double)quantum;
    const long double rq2 = std::ceil(rq * rq);
    return rq2 >= 9223372036854775808.0L ? std::uint64_t(1) << 63 : std::uint64_t(rq2);
}

// The radii of a plan whose lattice and base grid are set: their squares in lattice units, the
// neighbourhood reaches, and the quadtree's depth.
void set_radii(Plan& plan, double rf, double rc, bool two, const Box& box) {
    shared::Domain& d = plan.domain;
    d.radii.inhibition2 = squared_units(rf, plan.quantum);
    d.radii.coverage2 = two ? squared_units(rc, plan.quantum) : d.radii.inhibition2;
    d.radii.kind = two ? shared::RADII_TWO : shared::RADII_ONE;
    if (two && d.radii.coverage2 > shared::MAX_COVER2)
        throw Error("internal: Rc is past the lattice steps the exact T test handles");
    const std::uint64_t cell_side = std::uint64_t(1) << d.cell_bits;
    // A sample must cover its whole base cell, so that an occupied base cell needs no darts.
    if (d.radii.inhibition2 <= 2 * (cell_side - 1) * (cell_side - 1))
        throw Error("internal: base cell diagonal is not shorter than the radius");
    // Rows/columns of base cells a disk of squared radius limit2 reaches across.
    auto reach_of = [&](std::uint64_t limit2) {
        std::uint32_t n = 1;
        while (shared::cell_gap2(d, int(n) + 1, 0) < limit2) ++n;
        return n;
    };
    const std::uint32_t conflict = reach_of(d.radii.inhibition2);
    const std::uint32_t cover = reach_of(d.radii.coverage2 + 1);
    const std::uint32_t influence = two ? reach_of(shared::influence2(d.radii)) : conflict;
    if (conflict > shared::MAX_REACH || (d.lattice.periodic && (conflict > d.cells_x || conflict > d.cells_y)))
        throw Error("internal: a disk reaches further than the neighbourhood the kernels scan");
    if (two && d.lattice.periodic && (2 * influence + 1 > d.cells_x || 2 * influence + 1 > d.cells_y))
        throw Error(fmt::format(
            "Rc {} is too large for a periodic box of {} x {}: the 2 Rc neighbourhood must not wrap onto itself", rc,
            box.width, box.height));
    d.radii.reach = conflict | cover << 8 | influence << 16;
    for (std::uint32_t dy = 0; dy <= conflict; ++dy)
        d.radii.reach |= std::uint32_t(shared::computed_row_reach(d, int(dy), int(conflict), d.radii.inhibition2))
                         << (24 + 2 * dy);
    plan.deepest_level = d.cell_bits;
    plan.base_cells = std::uint64_t(d.cells_x) * d.cells_y;
}

}  // namespace

bool periodic_tiling(double width, double height, double max_side, std::uint64_t multiple, std::uint64_t& nx,
                     std::uint64_t& ny) {
    std::uint64_t first = std::uint64_t(std::ceil(width / max_side));
    // Cells no smaller than r/3 keep a disk's reach within MAX_REACH cells.
    const std::uint64_t last = std::uint64_t(std::floor(width / (max_side * std::sqrt(2.0) / 3.0)));
    for (std::uint64_t n = first; n <= last; ++n) {
        double side = width / double(n);
        double rows = height / side;
        double whole = std::round(rows);
        if (n % multiple != 0 || std::uint64_t(whole) % multiple != 0) continue;
        if (whole >= 1.0 && std::abs(rows - whole) <= 1e-9 * rows && height / whole <= max_side) {
            nx = n;
            ny = std::uint64_t(whole);
            return true;
        }
    }
    return false;
}

double hierarchy_start(const SampleOptions& o) {
    if (o.hierarchy.start != 0) return o.hierarchy.start;
    return o.hierarchy.continuous ? 10.0 : double(o.hierarchy.steps);
}

std::vector<glm::uvec2> given_on_lattice(const SampleOptions& o, double quantum, const shared::Lattice& lattice) {
    // Rounding up to the box's side wraps round a torus, and stays on the last point of a free box.
    auto axis = [&](double v, std::uint32_t extent) {
        const double u = std::round(v / quantum);
        return u >= double(extent) ? (lattice.periodic ? 0u : extent - 1) : std::uint32_t(u);
    };
    std::vector<glm::uvec2> out(o.initial.size());
    for (std::size_t i = 0; i < o.initial.size(); ++i) {
        const glm::dvec2 p = o.initial[i];
        if (!(p.x >= 0 && p.y >= 0 && p.x < o.box.width && p.y < o.box.height))
            throw Error(fmt::format("given sample {} ({}, {}) is outside the box [0,{}) x [0,{})", i + 1, p.x, p.y,
                                    o.box.width, o.box.height));
        out[i] = {axis(p.x, lattice.extent_x), axis(p.y, lattice.extent_y)};
    }
    return out;
}

std::vector<HierarchyStep> hierarchy_steps(const SampleOptions& o) {
    const unsigned steps = o.hierarchy.steps;
    if (o.hierarchy.continuous) return {{1.0, hierarchy_start(o)}};  // its first level; the rest have no steps
    if (steps == 0) return {{1.0, 1.0}};
    const double start = hierarchy_start(o), last = double(steps - 1);
    std::vector<HierarchyStep> out;
    for (unsigned k = 0; k < steps; ++k) {
        const double numerator = last * start - (start - 1) * double(k);
        out.push_back({numerator / (last * start), numerator / last});
    }
    return out;
}

}  // namespace vrpd::detail

namespace vrpd {
namespace {
// Extents, their squares and the box's area stay normal doubles.
void validate_box(const Box& box) {
    if (!detail::finite_positive(box.width) || !detail::finite_positive(box.height))
        throw Error(fmt::format("extent must be two finite numbers > 0 (got {},{})", box.width, box.height));
    for (const auto& [name, v] : {std::pair{"width", box.width}, {"height", box.height}})
        if (!(v >= kSmallestLength && v <= kLargestLength))
            throw Error(fmt::format("{} {} is outside the extents vrpd takes, {} to {}", name, v,
                                    kSmallestLength, kLargestLength));
}

// The checks of a hierarchy's steps and start, for every kind of run.
void validate_hierarchy(const SampleOptions& o) {
    const double start = detail::hierarchy_start(o);
    if (o.hierarchy.continuous && o.hierarchy.steps != 0)
        throw Error("a hierarchy is discrete (K steps) or continuous, not both");
    if (!o.hierarchy.continuous && (o.hierarchy.steps < 2 || o.hierarchy.steps > detail::kMaxSteps))
        throw Error(fmt::format("a hierarchy needs 2 to {} steps (got {})", detail::kMaxSteps, o.hierarchy.steps));
    if (!(start >= 1 && start <= detail::kMaxStart))
        throw Error(fmt::format("a hierarchy's start S must be 1 to {} times the final radii (got {})",
                                detail::kMaxStart, start));
    if (!o.initial.empty()) throw Error("a hierarchy starts from no samples: give --from or --hierarchy, not both");
}

// A run with a sizing field: the field replaces the radii. A hierarchy's first step's field
// (discrete or continuous) is checked where it is tabulated (field/run.cpp).
void validate_sizing(const SampleOptions& o) {
    if (o.radius != 0 || o.coverage != 0) throw Error("give a sizing field or radii, not both");
    if (o.hierarchy.continuous || o.hierarchy.steps != 0) validate_hierarchy(o);
    if (o.threads > detail::kMaxThreads)
        throw Error(fmt::format("threads must be at most {} (got {})", detail::kMaxThreads, o.threads));
    validate_box(o.box);
    // The field itself is checked where it is tabulated (field/table.cpp).
}

// The checks of one run at the options' radii (a hierarchy's steps each pass them).
void validate_run(const SampleOptions& o) {
    if (!std::isfinite(o.radius)) throw Error("radius must be a finite number");
    if (o.radius <= 0.0) throw Error(fmt::format("radius must be > 0 (got {})", o.radius));
    // A radius far above the box is fine (the plan clamps its square), one below the smallest
    // extent is refused by the cell count.
    validate_box(o.box);
    for (const auto& [name, v] : {std::pair{"radius", o.radius}, {"coverage radius", o.coverage}})
        if (std::isfinite(v) && v != 0.0 && v < kSmallestLength)
            throw Error(
                fmt::format("{} {} is below the smallest length vrpd takes, {}", name, v, kSmallestLength));
    if (o.threads > detail::kMaxThreads)
        throw Error(fmt::format("threads must be at most {} (got {})", detail::kMaxThreads, o.threads));
    double short_side = std::min(o.box.width, o.box.height);
    if (o.box.boundary == Boundary::Periodic && o.radius >= short_side / 2.0)
        throw Error(
            fmt::format("radius {} is too large for a periodic box of {} x {}: it must be < {} (half the shorter side)",
                        o.radius, o.box.width, o.box.height, short_side / 2.0));
    if (o.coverage == 0.0) return;
    if (!std::isfinite(o.coverage) || o.coverage < o.radius)
        throw Error(
            fmt::format("coverage radius Rc must be a finite number >= the inhibition radius Rf (got Rc {}, Rf {})",
                        o.coverage, o.radius));
    if (o.coverage != o.radius &&
        o.coverage / o.radius < detail::kMinCoverageRatio * (1 - 1e-12))  // 0.011 / 0.01 passes
        throw Error(fmt::format("Rc / Rf = {:.6g} is below the supported {} (for Rc = Rf, use --radius)",
                                o.coverage / o.radius, detail::kMinCoverageRatio));
    if (o.coverage > detail::kMaxCoverageRatio * o.radius)
        throw Error(fmt::format("Rc / Rf = {:.6g} is above the supported {}", o.coverage / o.radius,
                                detail::kMaxCoverageRatio));
    if (o.box.boundary == Boundary::Periodic && o.coverage >= short_side / 4.0)
        throw Error(
            fmt::format("Rc {} is too large for a periodic box of {} x {}: with two radii it must be < {} "
                        "(a quarter of the shorter side)",
                        o.coverage, o.box.width, o.box.height, short_side / 4.0));
}
}  // namespace

void validate(const SampleOptions& o) {
    if (o.sizing) return validate_sizing(o);
    validate_run(o);
    if (o.hierarchy.continuous || o.hierarchy.steps != 0) {
        validate_hierarchy(o);
        const double start = detail::hierarchy_start(o);
        // The first step must be a valid run of its own.
        SampleOptions first = o;
        first.hierarchy = {};
        first.radius *= start;
        first.coverage *= start;
        try {
            validate_run(first);
        } catch (const Error& e) {
            throw Error(fmt::format("the hierarchy's first step, at {} times the radii: {}", start, e.what()));
        }
    }
}
}  // namespace vrpd

namespace vrpd::detail {

Plan make_plan(const SampleOptions& o, std::uint32_t max_cell_bits) {
    validate(o);
    // The lattice and base grid come from the smallest radius the run meets (radii.h): Rf, with
    // one radius or two. Base cells of diagonal below it hold at most one sample.
    const double r = o.radius;
    const double max_side = r / std::sqrt(2.0);
    const double longest = std::max(o.box.width, o.box.height);
    constexpr std::uint64_t max_cells_per_row = kLatticeLimit >> kMinCellBits;
    auto too_wide = [&] {
        return Error(
            fmt::format("the box is {:.3g} radii across: at most {} base cells per side fit the 31-bit lattice",
                        longest / r, max_cells_per_row));
    };
    // Checked in doubles first: a box 10^300 radii across does not convert to an integer count.
    // The tiling may make cells smaller than max_side, so the count is checked again below.
    if (longest / max_side > double(max_cells_per_row)) throw too_wide();
    std::uint64_t nx = 0, ny = 0;
    double side = max_side;
    const std::uint32_t group_bits = hierarchy_levels(o);
    const std::uint64_t group = std::uint64_t(1) << group_bits;
    if (o.box.boundary == Boundary::Periodic) {
        if (!periodic_tiling(o.box.width, o.box.height, max_side, group, nx, ny))
            throw Error(fmt::format("periodic box {} x {}: width/height must be a ratio of small integers so that "
                                    "square cells of side <= r/sqrt(2) tile it", o.box.width, o.box.height));
        side = o.box.width / double(nx);
    } else {
        // Any side <= r/sqrt(2) works; capping it at the box keeps 2^30 lattice steps across the
        // box when r dwarfs it, so the first sample is still uniform over the box.
        side = std::min(side, std::max(o.box.width, o.box.height));
        nx = (std::uint64_t(std::ceil(o.box.width / side)) + group - 1) / group * group;
        ny = (std::uint64_t(std::ceil(o.box.height / side)) + group - 1) / group * group;
    }
    const std::uint64_t cells_per_row = std::max(nx, ny);
    // Base cells are numbered, and active lists counted, in 31 bits (the grid tag bit).
    if (nx * ny >= (std::uint64_t(1) << 31))
        throw Error(fmt::format("the box is {:.3g} radii across: {} base cells, more than the 2^31 the kernels index",
                                longest / r, nx * ny));
    if (cells_per_row > max_cells_per_row) throw too_wide();
    // Two radii: Rc is at most 2^19 lattice units, the bound under which t_membership.h's exact
    // circle-intersection tests fit 128-bit products.
    // A free box whose diagonal is shorter than Rf holds one sample, which covers it whatever
    // Rc >= Rf: the one-radius run at Rf gives it, uniform over the box, where two radii's
    // neighbourhoods would reach further than the kernels scan.
    const bool one_sample = o.box.boundary == Boundary::Free && o.radius > std::hypot(o.box.width, o.box.height);
    const bool two = o.coverage != 0.0 && o.coverage != o.radius && !one_sample;
    // A hierarchy's coarser grids add up to group_bits to the cell bits, and its first step has
    // S times the radii.
    const std::uint32_t top = std::min<std::uint32_t>(30 - group_bits, max_cell_bits);
    std::uint32_t bits = std::min(kMinCellBits, top);
    const double largest_rc = o.coverage * (o.hierarchy.steps == 0 ? 1.0 : hierarchy_start(o));
    auto fits = [&](std::uint32_t b) {
        const double rc_units = largest_rc / (side / double(1u << b));
        return (cells_per_row << b) <= kLatticeLimit &&
               (!two || rc_units * rc_units < double(shared::MAX_COVER2) * 0.999);
    };
    while (bits < top && fits(bits + 1)) ++bits;
    if (!fits(bits)) throw Error("internal: no lattice resolution fits the radii");

    Plan plan{};
    shared::Domain& d = plan.domain;
    plan.quantum = side / double(1u << bits);
    d.cells_x = std::uint32_t(nx);
    d.cells_y = std::uint32_t(ny);
    d.cell_bits = bits;
    d.lattice.periodic = o.box.boundary == Boundary::Periodic ? 1u : 0u;
    plan.seed = o.seed;
    if (d.lattice.periodic) {
        d.lattice.extent_x = std::uint32_t(nx << bits);
        d.lattice.extent_y = std::uint32_t(ny << bits);
    } else {
        // Lattice points x with x * quantum < width.
        d.lattice.extent_x = std::uint32_t(std::min<double>(std::ceil(o.box.width / plan.quantum), double(nx << bits)));
        d.lattice.extent_y =
            std::uint32_t(std::min<double>(std::ceil(o.box.height / plan.quantum), double(ny << bits)));
    }
    set_radii(plan, r, two ? o.coverage : r, two, o.box);
    return plan;
}

Plan step_plan(const Plan& finest, const SampleOptions& o, double scale) {
    Plan plan = finest;
    const double rf = o.radius * scale, rc = (o.coverage == 0.0 ? o.radius : o.coverage) * scale;
    const bool one_sample = o.box.boundary == Boundary::Free && rf > std::hypot(o.box.width, o.box.height);
    const bool two = o.coverage != 0.0 && o.coverage != o.radius && !one_sample;
    // The coarsest grouping of the finest cells that a sample still covers whole.
    std::uint32_t j = hierarchy_levels(o);
    const std::uint64_t rf2 = squared_units(rf, plan.quantum);
    auto covers = [&](std::uint32_t g) {
        const std::uint64_t side = std::uint64_t(1) << (finest.domain.cell_bits + g);
        return rf2 > 2 * (side - 1) * (side - 1);
    };
    while (j > 0 && !covers(j)) --j;
    shared::Domain& d = plan.domain;
    d.cells_x = finest.domain.cells_x >> j;
    d.cells_y = finest.domain.cells_y >> j;
    d.cell_bits = finest.domain.cell_bits + j;
    set_radii(plan, rf, rc, two, o.box);
    return plan;
}

std::uint64_t expected_samples(const Plan& plan) {
    // RSA jams at n r^2 = 0.6966 per unit area; with two radii n Rc^2 rises from there to about
    // 0.94 at Rc = 2 Rf (section 3). The smaller of the two bounds, over the box's lattice area.
    const shared::Domain& d = plan.domain;
    const double area = double(d.lattice.extent_x) * double(d.lattice.extent_y);
    const double n = std::min(0.70 * area / double(d.radii.inhibition2), 0.95 * area / double(d.radii.coverage2));
    return std::uint64_t(n) + 64;
}

std::uint64_t estimated_bytes(const Plan& plan) {
    // The engines' arrays stay within 48 bytes per base cell (estimated_device_bytes; a test
    // holds every engine to it).
    // On a CPU Vulkan device those arrays are host memory too, beside the driver's own (about
    // 155 MiB for lavapipe with LLVM) and the program.
    return plan.base_cells * 48 + (std::uint64_t(256) << 20);
}

std::uint64_t estimated_device_bytes(const Plan& plan) {
    // The first round's peak, per base cell: grid word 8, the scratch regions (prefix sums 4,
    // work list 2 at lambda = 0.5; see VulkanEngine::Scratch), the darts 8 and the samples about
    // 3; mask mode keeps no active list there. Two radii keep the lists, and more.
    return plan.base_cells * 48 + (std::uint64_t(16) << 20);
}

namespace {
// A cgroup's memory limit from its control file: a number of bytes, or "max" (none).
std::uint64_t cgroup_limit(const char* path) {
    std::ifstream in(path);
    std::uint64_t bytes = 0;
    return in >> bytes ? bytes : UINT64_MAX;
}
}  // namespace

MemoryLimit host_memory_limit() {
    MemoryLimit limit{std::uint64_t(sysconf(_SC_PHYS_PAGES)) * std::uint64_t(sysconf(_SC_PAGE_SIZE)),
                      "physical memory"};
    rlimit as{};
    if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY && as.rlim_cur < limit.bytes)
        limit = {std::uint64_t(as.rlim_cur), "address-space limit (ulimit -v)"};
    for (const char* file : {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"}) {
        const std::uint64_t bytes = cgroup_limit(file);
        if (bytes < limit.bytes) limit = {bytes, "cgroup memory limit"};
    }
    return limit;
}

}  // namespace vrpd::detail
