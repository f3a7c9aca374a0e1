// vrpd: maximal Poisson-disk sampling on Vulkan compute, with CPU backends that give the same points.
// Implements sections 1 and 3 (two radii) of Mitchell, Rand, Ebeida, Bajaj, "Variable Radii Poisson-Disk Sampling".
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

namespace vrpd {

// Every failure the library reports: a one-line reason, never a print or an exit.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

enum class Boundary { Periodic, Free };
// Where a run's rounds execute. Every backend gives the same points, byte for byte.
//   Auto:   a hardware Vulkan device (discrete, integrated or virtual GPU) when one is usable,
//           else Cpu; a named Vulkan device (SampleOptions::device or $VRPD_DEVICE) means Gpu.
//   Gpu:    Vulkan compute on the chosen device, CPU drivers such as Mesa lavapipe included.
//   Cpu:    the same kernel bodies on the host's threads.
//   Serial: the same darts accepted one at a time in arrival order: the textbook oracle.
enum class Backend { Auto, Gpu, Cpu, Serial };

// The axis-aligned box [0, width) x [0, height): a torus (the paper's setting) or a free boundary,
// where samples lie inside the box, coverage is required inside it and distance is Euclidean.
// The lengths vrpd takes: box extents within [kSmallestLength, kLargestLength], radii at least
// kSmallestLength (and, in verify, at most kLargestLength). Their squares, products and the box's
// area stay normal doubles, so every distance test means what it says at any scale in between.
inline constexpr double kSmallestLength = 1e-100;
inline constexpr double kLargestLength = 1e100;

struct Box {
    double width = 1.0;
    double height = 1.0;
    Boundary boundary = Boundary::Periodic;
};

// A hierarchy of samplings (paper section 4): radii t (Rf0, Rc0) with Rf0 = S Rf and Rc0 = S Rc (Rf,
// Rc the final radii), t stepping down in K steps t_k = 1 - (1 - 1/S) k / (K - 1), k = 0..K-1
// (K = S = 10: 10, 9, ..., 1 times the final radii), each step continuing the sampling until it
// is maximal at t_k (Rf0, Rc0). Every sample records the t_k at which it was born, so the samples
// with t >= t_k are a maximal sampling at t_k (Rf0, Rc0): a prefix of the output, which is in
// birth order. With a sizing field r(x) (discrete only) the level at t_k has the field t_k S r(x):
// the final field's table on its lattice, each node scaled and rounded (SizingField::scaled), so
// r at a point only shrinks from level to level.
// A continuous hierarchy (section 4.2, `continuous`; steps 0) lowers t without steps from a
// direct sampling at t = 1, inserting a sample where the sampling first stops being maximal; it is
// built on CGAL's Delaunay triangulation, by vrpd_geometry's continuous_hierarchy (vrpd/continuous.h).
struct HierarchyOptions {
    unsigned steps = 0;       // K >= 2; 0: no discrete hierarchy
    double start = 0;         // S >= 1; 0: S = K
    bool continuous = false;  // a continuous hierarchy from S (start; 0: 10) times the final radii
};

struct VulkanTarget;  // vrpd/vulkan_target.h

// Spatially varying radii (paper section 5). Table 1's conflict rules: f(x, y) for an earlier
// sample x and a later point y is r(x) (prior), r(y) (current), max (bigger) or min (smaller),
// both for the empty-disk property (Eq. 10: no later sample y with |x - y| < f) and for coverage
// (Eq. 11: every point y has a sample x with |x - y| < f).
enum class SizingRule { Prior, Current, Bigger, Smaller };
// Where each new sample lands: uniform over the uncovered set (Eq. 4), or with density
// proportional to 1 / r(x)^2 there (Eq. 12).
enum class Weighting { Uniform, Density };

// A sizing field r(x) and its rule. The field is the expression (vrpd/sizing.h's language), or a
// greyscale PNG or binary PGM image mapped onto the box with r = r_min + (r_max - r_min) grey
// (dark = small radius = dense; a colour file whose pixels are all grey is read as grey). The
// sampler tabulates it once, in fixed point on a grid fine enough that the interpolant stays
// within 0.1 % of it where the lattice and the table's budget allow (a kink may take more:
// table_budget; the measured error is in Sampling::field), and r at a lattice point is that
// table's bilinear interpolant in integers: the same number on every backend.
struct Sizing {
    std::string expression;      // or
    std::string image;           // a path
    double r_min = 0, r_max = 0; // the image's radii, 0 < r_min <= r_max
    double lipschitz = -1;       // >= 0: use the largest L-Lipschitz field below r (on the table's nodes)
    SizingRule rule = SizingRule::Smaller;
    Weighting weighting = Weighting::Uniform;
    // The table words a sample the field's patches and kinked cells may take where the table
    // strays from the source (kinks, sharp bends): more brings such a field closer to it, at that
    // memory (1 to 1024).
    double table_budget = 32;
};

struct SampleOptions {
    double radius = 0.0;         // inhibition radius Rf: no two samples closer (paper Eq. 5)
    double coverage = 0.0;       // coverage radius Rc, Rf <= Rc <= 4 Rf: every point within Rc of a
                                 // sample (Eq. 8); 0: equal to radius, the classical one-radius case
    Box box;
    std::uint32_t seed = 0;
    Backend backend = Backend::Auto;
    std::string device;          // Vulkan device by index or name substring; empty: $VRPD_DEVICE, else the best
    unsigned threads = 0;        // host threads of the cpu backend; 0: one per core. Never changes the points.
    bool profile = false;        // fill SamplingStats::profile. Never changes the points.
    HierarchyOptions hierarchy;
    // Samples the run starts from (and outputs first, unchanged but for rounding to the run's
    // lattice, by at most half a lattice step): they must lie in the box and be conflict-free at
    // Rf on that lattice (with a sizing field: under its rule, in their order, as the earlier
    // samples). The run adds samples until the set is maximal.
    std::vector<glm::dvec2> initial;
    // Run on the application's Vulkan device (vrpd/vulkan_target.h; Gpu backend) instead of one
    // vrpd opens; not owned.
    const VulkanTarget* vulkan = nullptr;
    // A sizing field r(x) instead of radius and coverage (which stay 0): the samples are
    // conflict-free and maximal under its rule, each with r at it in Sampling::local_radius.
    std::optional<Sizing> sizing;
};

// Where a run's time went: one phase of the host engines, or one kernel of the Vulkan engine
// (timed on the device with timestamps: from the end of the work before it to its own end, so
// the barrier and any buffer fill before a dispatch count towards it).
struct PhaseTime {
    std::string name;
    double seconds = 0.0;
    std::uint64_t calls = 0;     // times the phase ran (rounds, or dispatches)
};

// A sizing field as a run tabulated it (Sizing).
struct FieldStats {
    double r_min = 0, r_max = 0;   // r's range over the box, in box units
    double lipschitz = 0;          // the interpolant's, exactly (its largest gradient, at a table cell's corner)
    double tabulation_error = 0;   // the largest |table - source| / source found at the table cells' centres
                                   // and edge midpoints
    std::uint64_t table_nodes = 0;
};

struct SamplingStats {
    std::uint32_t levels = 0;    // flat-quadtree levels visited (0 = base cells)
    std::uint32_t rounds = 0;    // dart rounds thrown
    std::uint64_t darts = 0;     // darts thrown in all rounds
    double seconds = 0.0;        // wall time of the sampling, setup and read-back included
    std::uint64_t peak_bytes = 0; // the most memory the sampler's own arrays held at once: device
                                  // memory (gpu) or host arrays (cpu, serial); the process's
                                  // resident memory adds the program and the Vulkan driver
    std::vector<PhaseTime> profile;   // with SampleOptions::profile: phases in the order they first ran
    std::uint64_t round_trips = 0;    // submits the host waited on (Vulkan; 0 on the host backends),
                                      // setup and read-back included: each costs a real GPU a
                                      // queue's latency, however little work it carries
};

// A maximal sampling. Samples lie on an integer lattice of spacing `quantum` (exact predicates on
// every device); points are in acceptance order, the order of the paper's sequence x_1..x_n.
struct Sampling {
    std::vector<glm::uvec2> lattice;  // sample i is at lattice[i] * quantum
    double quantum = 0.0;
    double radius = 0.0;              // Rf
    double coverage = 0.0;            // Rc (equal to radius for one radius)
    Box box;
    Backend backend = Backend::Cpu;   // the backend that ran (never Auto)
    std::string device;               // the device that ran it, with its driver
    std::string choice;               // with Backend::Auto, why it picked that backend; else empty
    SamplingStats stats;

    // Per-sample attributes beside the position: each empty when the run has none, else one value
    // per sample, in sample order. Point files carry them as named columns (vrpd/io.h).
    std::vector<double> birth;         // column "t": the scale t at which the sample was born (section 4)
    double hierarchy_start = 1;        // a hierarchy's S: at birth t the radii were t S (radius, coverage)
    std::vector<double> local_radius;  // column "r": the radius at the sample (section 5)
    FieldStats field;                  // with a sizing field: the field as tabulated

    std::size_t size() const { return lattice.size(); }
    glm::dvec2 point(std::size_t i) const {
        return {double(lattice[i].x) * quantum, double(lattice[i].y) * quantum};
    }
};

Sampling sample(const SampleOptions& options);

// Checks the options (radius, box) and throws Error with the reason if they cannot be sampled.
void validate(const SampleOptions& options);

struct DeviceInfo {
    std::uint32_t index;
    std::string name;
    std::string type;            // "discrete", "integrated", "virtual", "cpu", "other"
    std::string driver;
    bool usable;                 // has what vrpd needs (Vulkan 1.2, int64, buffer device address)
};

// The Vulkan devices on this machine; throws Error when no Vulkan loader or driver is present.
std::vector<DeviceInfo> list_devices();

// The backend a run of `options` uses: options.backend, or for Backend::Auto the one it picks,
// with the reason. Looks at the Vulkan devices only for Auto.
struct BackendChoice {
    Backend backend;
    std::string reason;          // empty unless options.backend is Auto
};
BackendChoice choose_backend(const SampleOptions& options);

const char* version();

}  // namespace vrpd
