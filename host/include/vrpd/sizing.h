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
    // Whether the program has one kink, the one step where its value can bend (an abs, min or
    // max not on constants alone), and no clamp: then its value is one of two smooth branches.
    bool kinked() const { return kink_ >= 0; }
    // The two branches of the kink at n points: a[i] with the kink's first branch taken (abs: its
    // argument; min and max: their first operand), b[i] with its second (abs: the argument
    // negated; min and max: the second operand), and second[i] = 1 where the plain evaluation
    // takes the second (so that its value is b[i], else a[i]). Requires kinked().
    void branches(const double* x, const double* y, double* a, double* b, std::uint8_t* second, std::size_t n,
                  const Box& box) const;
    // The plain values at n points, bit for bit operator()'s, and `second` as branches gives it.
    void taken(const double* x, const double* y, double* out, std::uint8_t* second, std::size_t n,
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
    // With `branch` 0 or 1 the kink step takes that branch, and second[i] says which the plain
    // evaluation takes; with -1 every step is the plain one, the kink's saying so too where
    // `second` is given.
    void run(const double* x, const double* y, double* out, std::size_t m, std::size_t stride, double* stack,
             const Box& box, int branch = -1, std::uint8_t* second = nullptr) const;
    // run over n points in batches, each step over a batch before the next.
    void batched(const double* x, const double* y, double* out, std::size_t n, const Box& box, int branch,
                 std::uint8_t* second) const;

    std::string text_;
    std::vector<Step> program_;
    std::size_t depth_ = 0;  // the stack the program needs
    std::ptrdiff_t kink_ = -1;  // the kink's step, or -1
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
