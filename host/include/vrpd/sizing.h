// Sizing functions r(x) for spatially varying radii (paper section 5): a small, safe expression
// language, and the conflict rules of Table 1.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "vrpd/vrpd.h"

namespace vrpd {

namespace detail {
struct FieldTable;
}

// An expression in x, y (box coordinates), d (distance to the box's centre), w, h (the box), pi,
// numbers, + - * / ^ (right-associative), unary minus, parentheses, and the functions abs, min,
// max, sqrt, sin, cos, exp, log (one argument, min and max two) and clamp(v, lo, hi). Parsed once
// into a stack program; evaluating it allocates nothing and cannot fail (NaN and inf are values,
// which users of the field refuse).
class SizingExpression {
public:
    // Throws Error for a malformed expression: the message names what was expected and shows the
    // expression with a caret under the place, on the lines after the first.
    explicit SizingExpression(std::string text);
    double operator()(double x, double y, const Box& box) const;
    // out[i] = r(x[i], y[i]) for i < n, bit for bit the values above: each step of the program
    // runs over a batch of points, so its dispatch is paid once per batch, not once per point.
    void operator()(const double* x, const double* y, double* out, std::size_t n, const Box& box) const;
    const std::string& text() const { return text_; }
    // The most kinks a field's branches are told apart by (see kinked); a branch mask has a bit
    // each, and the masks stay below 0xff.
    static constexpr std::size_t kMaxKinks = 7;
    // Whether the program has from one to kMaxKinks kinks, the steps where its value can bend (an
    // abs, min or max not on constants alone; a clamp is two, its max and then its min): then its
    // value at each point is one of its smooth branches, the program with each kink's branch
    // fixed. Kink k (in program order) is bit k of a branch mask: 0 its first branch (abs: its
    // argument; min and max: their first operand), 1 its second (abs: the argument negated; min
    // and max: the second operand).
    bool kinked() const { return kinks_ >= 1 && kinks_ <= kMaxKinks; }
    std::size_t kinks() const { return kinks_; }
    // The plain values at n points, bit for bit operator()'s, and in mask[i] the branch each kink
    // takes there (std::abs(v) is -v where v < 0, std::min(a, b) is b where b < a, std::max(a, b)
    // is b where a < b). Requires kinked().
    void taken(const double* x, const double* y, double* out, std::uint8_t* mask, std::size_t n, const Box& box) const;
    // The branch mask[i] gives at each of n points: every kink takes the branch of its bit.
    // Requires kinked().
    void forced(const double* x, const double* y, double* out, const std::uint8_t* mask, std::size_t n,
                const Box& box) const;

    // In this order: the values, then the binary operators, then the rest (the stack depth relies on it).
    enum class Op : std::uint8_t {
        Number, X, Y, D, W, H, Add, Sub, Mul, Div, Pow, Neg, Abs, Min, Max, Sqrt, Sin, Cos, Exp, Log, Clamp
    };
    // Where a binary operator's constant operand is: both on the stack, or one of them `value`.
    enum class Constant : std::uint8_t { None, Right, Left };
    struct Step {
        Op op;
        double value;  // Number's, or a binary operator's constant operand
        Constant constant = Constant::None;
    };

private:
    // Runs the program over m <= stride points (see the definition). With `force`, each kink takes
    // the branch its bit there gives; with `mask`, the branches the kinks take are written there.
    void run(const double* x, const double* y, double* out, std::size_t m, std::size_t stride, double* stack,
             const Box& box, const std::uint8_t* force = nullptr, std::uint8_t* mask = nullptr) const;
    // run over n points in batches, each step over a batch before the next.
    void batched(const double* x, const double* y, double* out, std::size_t n, const Box& box,
                 const std::uint8_t* force, std::uint8_t* mask) const;

    std::string text_;
    std::vector<Step> program_;
    std::size_t depth_ = 0;  // the stack the program needs
    std::size_t kinks_ = 0;  // the kinks' bits (a clamp has two)
};

// The field a run of `sizing` over `box` samples (vrpd.h, Sizing): its source tabulated in fixed
// point, r at a lattice point the table's integer interpolant. Throws Error as sample would.
// The source is evaluated on `threads` threads (0: one per hardware thread); the table does not
// depend on the count, nor on the sizing's rule and weighting, which are the run's.
class SizingField {
public:
    SizingField(const Sizing& sizing, const Box& box, unsigned threads = 0);
    // The field of a run's options: o.sizing over o.box, on the threads the run takes (one for
    // the serial backend, else o.threads). Throws Error if the options have no sizing.
    explicit SizingField(const SampleOptions& o);
    // r at the lattice point nearest p (clamped into the box), in box units.
    double operator()(glm::dvec2 p) const;
    FieldStats stats() const;
    double quantum() const;
    const detail::FieldTable& table() const { return *table_; }
    // Whether this is the field `sizing` gives over `box`: the same source (expression, or image
    // and its radii), Lipschitz limit and table budget, and the same box. The rule and weighting
    // may differ. A scaled field is no sizing's.
    bool made_from(const Sizing& sizing, const Box& box) const;
    // This field times `scale` (> 0) on the same lattice, each node of its table rounded: a
    // discrete hierarchy's field at birth t is its final field scaled by S t. Throws Error for a
    // scale that is not a finite number > 0 or passes the lattice's 32-bit radii. Its bounds are
    // found on `threads` threads (0: one per hardware thread).
    SizingField scaled(double scale, unsigned threads = 0) const;

private:
    SizingField(std::shared_ptr<const detail::FieldTable> table, const Sizing& sizing, const Box& box, double scale)
        : table_(std::move(table)), sizing_(sizing), box_(box), scale_(scale) {}
    std::shared_ptr<const detail::FieldTable> table_;  // shared by the field's copies
    Sizing sizing_;
    Box box_;
    double scale_ = 1;
};

// Samples `field`, tabulated before, where sample(options) would tabulate options.sizing again:
// the same points, without the tabulation's time. Runs with several seeds, rules or weightings,
// or from given samples, share one table so, on several threads at once too (a field is never
// written after it is made). Throws Error unless the field was made from options.sizing and
// options.box (SizingField::made_from).
Sampling sample(const SampleOptions& options, const SizingField& field);

// Table 1's conflict rules (SizingRule, vrpd.h) by name.
SizingRule parse_sizing_rule(const std::string& name);  // throws Error naming the four
const char* sizing_rule_name(SizingRule rule);
double rule_radius(SizingRule rule, double r_earlier, double r_later);

// Table 1's bound on the field's Lipschitz constant for each rule, under which the quality
// guarantees hold: 1/2 for prior and bigger, 1 for current and smaller.
double rule_lipschitz_bound(SizingRule rule);

// A sizing field as a function of a point of the box.
using SizingFunction = std::function<double(glm::dvec2)>;

// A field's range and measured Lipschitz constant, on a (n + 1) x (n + 1) grid of nodes over the
// box (neighbours along rows, columns and diagonals). Throws Error naming a node where r is not
// a finite number > 0.
struct FieldSummary {
    double r_min = 0, r_max = 0, lipschitz = 0;
    std::size_t nodes_per_side = 0;
};
FieldSummary summarize_field(const SizingFunction& r, const Box& box, std::size_t n = 256);
inline FieldSummary summarize_field(const SizingExpression& r, const Box& box, std::size_t n = 256) {
    return summarize_field([&](glm::dvec2 p) { return r(p.x, p.y, box); }, box, n);
}

// A point set judged under a sizing field and rule, in file order (the order of acceptance):
// conflicts (Eq. 10): pairs closer than f(r(earlier), r(later)) - tolerance, found exactly;
// coverage (Eq. 11): every node of a grid of spacing `resolution` within f(r(x), r(y)) +
// tolerance of some sample x, each sample reaching r(x) / (1 - L) with the summary's L (L < 1;
// else the field's largest r). The grid can miss an uncovered sliver thinner than its spacing.
struct SizingReport {
    FieldSummary field;
    std::size_t points = 0;
    std::uint64_t conflicts = 0;
    std::size_t first_a = 0, first_b = 0;  // the first conflicting pair found (1-based), if any
    double resolution = 0;                 // the coverage grid's spacing
    std::uint64_t grid_points = 0, uncovered = 0;
    double worst_ratio = 0;                // max over grid points of (nearest cover distance / f)
    glm::dvec2 worst_point{0, 0};
    bool passed() const { return conflicts == 0 && uncovered == 0; }
};
// The coverage runs on `threads` threads (0: one per hardware thread), which call r at once.
SizingReport check_sizing(const std::vector<glm::dvec2>& points, const SizingFunction& r, SizingRule rule,
                          const Box& box, double tolerance, const FieldSummary& field, unsigned threads = 0);
inline SizingReport check_sizing(const std::vector<glm::dvec2>& points, const SizingExpression& r, SizingRule rule,
                                 const Box& box, double tolerance) {
    return check_sizing(points, [&](glm::dvec2 p) { return r(p.x, p.y, box); }, rule, box, tolerance,
                        summarize_field(r, box));
}

}  // namespace vrpd
