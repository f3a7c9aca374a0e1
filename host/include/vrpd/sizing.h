// Sizing functions r(x) for spatially varying radii (paper section 5): a small, safe expression
// language, and the conflict rules of Table 1.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "vrpd/vrpd.h"

namespace vrpd {

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
    const std::string& text() const { return text_; }

    // In this order: the values, then the binary operators, then the rest (the stack depth relies on it).
    enum class Op : std::uint8_t {
        Number, X, Y, D, W, H, Add, Sub, Mul, Div, Pow, Neg, Abs, Min, Max, Sqrt, Sin, Cos, Exp, Log, Clamp
    };
    struct Step {
        Op op;
        double value;  // Number's
    };

private:
    std::string text_;
    std::vector<Step> program_;
    std::size_t depth_ = 0;  // the stack the program needs
};

// Table 1's conflict rules: f(x, y) for an earlier sample x and a later point y is r(x) (prior),
// r(y) (current), max (bigger) or min (smaller), for the empty-disk property (Eq. 10) and for
// coverage (Eq. 11).
enum class SizingRule { Prior, Current, Bigger, Smaller };
SizingRule parse_sizing_rule(const std::string& name);  // throws Error naming the four
const char* sizing_rule_name(SizingRule rule);
double rule_radius(SizingRule rule, double r_earlier, double r_later);

// Table 1's bound on the field's Lipschitz constant for each rule, under which the quality
// guarantees hold: 1/2 for prior and bigger, 1 for current and smaller.
double rule_lipschitz_bound(SizingRule rule);

// A field's range and measured Lipschitz constant, on a (n + 1) x (n + 1) grid of nodes over the
// box (neighbours along rows, columns and diagonals). Throws Error naming a node where r is not
// a finite number > 0.
struct FieldSummary {
    double r_min = 0, r_max = 0, lipschitz = 0;
    std::size_t nodes_per_side = 0;
};
FieldSummary summarize_field(const SizingExpression& r, const Box& box, std::size_t n = 256);

// A point set judged under a sizing field and rule, in file order (the order of acceptance):
// conflicts (Eq. 10): pairs closer than f(r(earlier), r(later)) - tolerance, found exactly;
// coverage (Eq. 11): every node of a grid of spacing `resolution` within f(r(x), r(y)) +
// tolerance of some sample x. The grid can miss an uncovered sliver thinner than its spacing.
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
SizingReport check_sizing(const std::vector<glm::dvec2>& points, const SizingExpression& r, SizingRule rule,
                          const Box& box, double tolerance);

}  // namespace vrpd
