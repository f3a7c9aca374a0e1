// Sizing expressions (vrpd/sizing.h): a recursive-descent parser emitting a stack program.
//   expr    := term (('+' | '-') term)*
//   term    := unary (('*' | '/') unary)*
//   unary   := ('-' | '+') unary | power
//   power   := primary ('^' unary)?
//   primary := number | name | name '(' expr (',' expr)* ')' | '(' expr ')'
#include "vrpd/sizing.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>
#include <type_traits>

#include <fmt/format.h>

namespace vrpd {
namespace {

using Op = SizingExpression::Op;
using Step = SizingExpression::Step;
using Constant = SizingExpression::Constant;

constexpr std::size_t kMaxLength = 4096;  // characters
constexpr int kMaxNesting = 64;           // parentheses, calls and unary signs, so recursion stays shallow
constexpr std::size_t kMaxStack = 256;    // values a program holds at once (the nesting bound keeps it below)

struct Function {
    const char* name;
    Op op;
    int arguments;
};
constexpr Function kFunctions[] = {{"abs", Op::Abs, 1},   {"min", Op::Min, 2},  {"max", Op::Max, 2},
                                   {"sqrt", Op::Sqrt, 1}, {"sin", Op::Sin, 1},  {"cos", Op::Cos, 1},
                                   {"exp", Op::Exp, 1},   {"log", Op::Log, 1},  {"clamp", Op::Clamp, 3}};
struct Variable {
    const char* name;
    Op op;
};
constexpr Variable kVariables[] = {{"x", Op::X}, {"y", Op::Y}, {"d", Op::D}, {"w", Op::W}, {"h", Op::H}};

bool is_binary(Op op) { return (op >= Op::Add && op <= Op::Pow) || op == Op::Min || op == Op::Max; }
bool is_unary(Op op) { return op == Op::Neg || op == Op::Abs || (op >= Op::Sqrt && op <= Op::Log); }

// The operators' arithmetic, the one definition both the evaluation and the folding of constant
// operands use, so a folded program gives the unfolded one's doubles.
inline double binary(Op op, double a, double b) {
    switch (op) {
        case Op::Add:
            return a + b;
        case Op::Sub:
            return a - b;
        case Op::Mul:
            return a * b;
        case Op::Div:
            return a / b;
        case Op::Pow:
            return std::pow(a, b);
        case Op::Min:
            return std::min(a, b);
        default:
            return std::max(a, b);
    }
}
inline double unary(Op op, double a) {
    switch (op) {
        case Op::Neg:
            return -a;
        case Op::Abs:
            return std::abs(a);
        case Op::Sqrt:
            return std::sqrt(a);
        case Op::Sin:
            return std::sin(a);
        case Op::Cos:
            return std::cos(a);
        case Op::Exp:
            return std::exp(a);
        default:
            return std::log(a);
    }
}

// The parser's program with its constant operands folded: an operator on constants becomes their
// value, and a binary operator with one constant operand takes it as its step's value instead of
// from the stack. The same operations on the same doubles, in the same order, with fewer steps.
std::vector<Step> fold(const std::vector<Step>& program) {
    // The stack as the program leaves it: each entry a constant not yet emitted, or computed by
    // the steps of `out` from `start` on.
    struct Entry {
        bool constant;
        double value;
        std::size_t start;
    };
    std::vector<Entry> stack;
    std::vector<Step> out;
    // Emits constant entry k in its place; the later entries' steps move one on.
    auto materialize = [&](std::size_t k) {
        Entry& e = stack[k];
        if (!e.constant) return;
        out.insert(out.begin() + std::ptrdiff_t(e.start), Step{Op::Number, e.value});
        e.constant = false;
        for (std::size_t j = k + 1; j < stack.size(); ++j) ++stack[j].start;
    };
    for (const Step& s : program) {
        if (s.op == Op::Number) {
            stack.push_back({true, s.value, out.size()});
        } else if (s.op <= Op::H) {
            stack.push_back({false, 0, out.size()});
            out.push_back(s);
        } else if (is_unary(s.op)) {
            Entry& a = stack.back();
            if (a.constant)
                a.value = unary(s.op, a.value);
            else
                out.push_back(s);
        } else if (is_binary(s.op)) {
            const Entry b = stack.back();
            stack.pop_back();
            Entry& a = stack.back();
            if (a.constant && b.constant) {
                a.value = binary(s.op, a.value, b.value);
            } else if (b.constant) {
                out.push_back({s.op, b.value, Constant::Right});
            } else if (a.constant) {
                out.push_back({s.op, a.value, Constant::Left});
                a = {false, 0, b.start};
            } else {
                out.push_back(s);
            }
        } else {  // Clamp: its three operands on the stack
            for (std::size_t k = stack.size() - 3; k < stack.size(); ++k) materialize(k);
            stack.resize(stack.size() - 2);
            out.push_back(s);
        }
    }
    materialize(0);
    return out;
}

class Parser {
public:
    explicit Parser(const std::string& text) : s_(text) {}

    std::vector<Step> parse() {
        if (s_.size() > kMaxLength)
            throw Error(fmt::format("sizing expression: longer than {} characters", kMaxLength));
        skip();
        if (at_end()) fail("expected an expression");
        expr();
        skip();
        if (!at_end()) fail(fmt::format("unexpected '{}'", s_[pos_]));
        return std::move(out_);
    }

private:
    [[noreturn]] void fail(const std::string& what) const {
        // The expression on a line of its own (control characters shown as spaces), a caret below.
        std::string shown = s_.substr(0, 120);
        for (char& c : shown)
            if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
        const std::size_t column = std::min(pos_, shown.size());
        throw Error(fmt::format("sizing expression: {} at column {}\n  {}\n  {}^", what, pos_ + 1, shown,
                                std::string(column, ' ')));
    }
    bool at_end() const { return pos_ >= s_.size(); }
    void skip() {
        while (!at_end() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
    }
    bool take(char c) {
        skip();
        if (!at_end() && s_[pos_] == c) {
            ++pos_;
            return true;
        }
        return false;
    }
    void emit(Op op, double value = 0) { out_.push_back({op, value}); }
    void nest() {
        if (++nesting_ > kMaxNesting) fail(fmt::format("nested deeper than {}", kMaxNesting));
    }

    void expr() {
        term();
        for (;;) {
            if (take('+')) {
                term();
                emit(Op::Add);
            } else if (take('-')) {
                term();
                emit(Op::Sub);
            } else {
                return;
            }
        }
    }
    void term() {
        unary();
        for (;;) {
            if (take('*')) {
                unary();
                emit(Op::Mul);
            } else if (take('/')) {
                unary();
                emit(Op::Div);
            } else {
                return;
            }
        }
    }
    void unary() {
        nest();
        if (take('-')) {
            unary();
            emit(Op::Neg);
        } else if (take('+')) {
            unary();
        } else {
            power();
        }
        --nesting_;
    }
    void power() {
        primary();
        if (take('^')) {
            unary();
            emit(Op::Pow);
        }
    }
    void primary() {
        skip();
        if (at_end()) fail("expected a number, a name or '('");
        const char c = s_[pos_];
        if (c == '(') {
            ++pos_;
            nest();
            expr();
            if (!take(')')) fail("expected ')'");
            --nesting_;
            return;
        }
        if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
            double v = 0;
            const auto [end, ec] = std::from_chars(s_.data() + pos_, s_.data() + s_.size(), v);
            if (ec != std::errc() || !std::isfinite(v)) fail("malformed number");
            pos_ = std::size_t(end - s_.data());
            emit(Op::Number, v);
            return;
        }
        if (!std::isalpha(static_cast<unsigned char>(c))) fail(fmt::format("unexpected '{}'", c));
        const std::size_t start = pos_;
        while (!at_end() && std::isalnum(static_cast<unsigned char>(s_[pos_]))) ++pos_;
        const std::string name = s_.substr(start, pos_ - start);
        for (const Function& f : kFunctions) {
            if (name != f.name) continue;
            if (!take('(')) fail(fmt::format("expected '(' after {}", name));
            nest();
            for (int a = 0; a < f.arguments; ++a) {
                if (a > 0 && !take(',')) fail(fmt::format("{} takes {} arguments: expected ','", name, f.arguments));
                expr();
            }
            if (!take(')')) fail(fmt::format("{} takes {} argument{}: expected ')'", name, f.arguments,
                                             f.arguments == 1 ? "" : "s"));
            --nesting_;
            emit(f.op);
            return;
        }
        if (name == "pi") return emit(Op::Number, std::numbers::pi);
        for (const Variable& v : kVariables)
            if (name == v.name) return emit(v.op);
        pos_ = start;
        fail(fmt::format("unknown name '{}' (x, y, d, w, h, pi, abs, min, max, sqrt, sin, cos, exp, log, clamp)",
                         name));
    }

    const std::string& s_;
    std::size_t pos_ = 0;
    int nesting_ = 0;
    std::vector<Step> out_;
};

}  // namespace

SizingExpression::SizingExpression(std::string text) : text_(std::move(text)), program_(fold(Parser(text_).parse())) {
    // The stack depth the program reaches: a value pushes one, an operator pops its arity less one
    // (a binary operator with a constant operand takes one from the stack).
    std::size_t depth = 0;
    for (const Step& s : program_) {
        if (s.op <= Op::H) {
            ++depth;  // Number and the variables
        } else if (is_binary(s.op)) {
            if (s.constant == Constant::None) --depth;
        } else if (s.op == Op::Clamp) {
            depth -= 2;
        }
        depth_ = std::max(depth_, depth);
    }
    if (depth_ > kMaxStack) throw Error("sizing expression: too deeply nested to evaluate");
    // Folding left no abs, min or max on constants alone, so each of these steps can bend.
    for (const Step& s : program_) {
        if (s.op == Op::Clamp) kinks_ += 2;
        if (s.op == Op::Abs || s.op == Op::Min || s.op == Op::Max) ++kinks_;
    }
}

// Runs the program over m <= stride points: stack entry k of point i is stack[k * stride + i].
// Each step runs over all the points before the next, so its dispatch is paid once per batch;
// every point's arithmetic is the scalar evaluation's, in the same order.
void SizingExpression::run(const double* x, const double* y, double* out, std::size_t m, std::size_t stride,
                           double* stack, const Box& box, const std::uint8_t* force, std::uint8_t* mask) const {
    std::size_t n = 0;  // entries on the stack
    auto row = [&](std::size_t k) { return stack + k * stride; };
    // A binary operator: both operands on the stack, or one of them the step's constant. Each
    // operator's body is instantiated on its own (`op` a constant), so the loops stay tight.
    auto apply_binary = [&](auto op, const Step& s) {
        if (s.constant == Constant::None) {
            --n;
            double* a = row(n - 1);
            const double* b = row(n);
            for (std::size_t i = 0; i < m; ++i) a[i] = binary(op(), a[i], b[i]);
            return;
        }
        double* a = row(n - 1);
        const double c = s.value;
        if (s.constant == Constant::Right)
            for (std::size_t i = 0; i < m; ++i) a[i] = binary(op(), a[i], c);
        else
            for (std::size_t i = 0; i < m; ++i) a[i] = binary(op(), c, a[i]);
    };
    auto apply_unary = [&](auto op) {
        double* a = row(n - 1);
        for (std::size_t i = 0; i < m; ++i) a[i] = unary(op(), a[i]);
    };
    auto push = [&](auto value) {
        double* a = row(n++);
        for (std::size_t i = 0; i < m; ++i) a[i] = value(i);
    };
    // Kink `bit`, its branch forced or plain, writing the branch it takes into the mask where
    // one is given: std::abs(v) is -v where v < 0, std::min(a, b) is b where b < a, std::max(a, b)
    // is b where a < b.
    auto takes_second = [&](std::size_t i, unsigned bit, bool plain) {
        const bool second = force ? (force[i] >> bit & 1) != 0 : plain;
        if (mask) mask[i] = std::uint8_t(mask[i] | unsigned(second) << bit);
        return second;
    };
    auto apply_kink = [&](const Step& s, unsigned bit) {
        if (s.op == Op::Abs) {
            double* a = row(n - 1);
            for (std::size_t i = 0; i < m; ++i)
                // The first branch as std::abs gives it where it takes it: -0 + 0.0 is +0.
                a[i] = takes_second(i, bit, a[i] < 0) ? -a[i] : force ? a[i] + 0.0 : std::abs(a[i]);
            return;
        }
        if (s.constant == Constant::None) --n;
        double* a = row(n - 1);
        const double* b = row(n);
        for (std::size_t i = 0; i < m; ++i) {
            const double first = s.constant == Constant::Left ? s.value : a[i];
            const double other = s.constant == Constant::None ? b[i] : s.constant == Constant::Right ? s.value : a[i];
            a[i] = takes_second(i, bit, s.op == Op::Min ? other < first : first < other) ? other : first;
        }
    };
    // A clamp's two kinks: std::max(v, lo), then std::min(that, hi).
    auto apply_clamp = [&](unsigned bit) {
        n -= 2;
        double* a = row(n - 1);
        const double *lo = row(n), *hi = row(n + 1);
        for (std::size_t i = 0; i < m; ++i) {
            const double low = takes_second(i, bit, a[i] < lo[i]) ? lo[i] : a[i];
            a[i] = takes_second(i, bit + 1, hi[i] < low) ? hi[i] : low;
        }
    };
    if (mask) std::fill(mask, mask + m, std::uint8_t(0));
    unsigned bit = 0;  // the next kink's
    for (std::size_t k = 0; k < program_.size(); ++k) {
        const Step& s = program_[k];
        if (force || mask) {
            if (s.op == Op::Abs || s.op == Op::Min || s.op == Op::Max) {
                apply_kink(s, bit++);
                continue;
            }
            if (s.op == Op::Clamp) {
                apply_clamp(bit);
                bit += 2;
                continue;
            }
        }
        switch (s.op) {
        case Op::Number: push([&](std::size_t) { return s.value; }); break;
        case Op::X: push([&](std::size_t i) { return x[i]; }); break;
        case Op::Y: push([&](std::size_t i) { return y[i]; }); break;
        case Op::D:
            // Box sides within 1e-100 to 1e100 keep the squares far from overflow and underflow,
            // so the plain formula is as good as hypot's guarded one, at a fifth of its cost.
            push([&](std::size_t i) {
                const double dx = x[i] - box.width / 2, dy = y[i] - box.height / 2;
                return std::sqrt(dx * dx + dy * dy);
            });
            break;
        case Op::W: push([&](std::size_t) { return box.width; }); break;
        case Op::H: push([&](std::size_t) { return box.height; }); break;
        case Op::Add:
            apply_binary(std::integral_constant<Op, Op::Add>{}, s);
            break;
        case Op::Sub:
            apply_binary(std::integral_constant<Op, Op::Sub>{}, s);
            break;
        case Op::Mul:
            apply_binary(std::integral_constant<Op, Op::Mul>{}, s);
            break;
        case Op::Div:
            apply_binary(std::integral_constant<Op, Op::Div>{}, s);
            break;
        case Op::Pow:
            apply_binary(std::integral_constant<Op, Op::Pow>{}, s);
            break;
        case Op::Min:
            apply_binary(std::integral_constant<Op, Op::Min>{}, s);
            break;
        case Op::Max:
            apply_binary(std::integral_constant<Op, Op::Max>{}, s);
            break;
        case Op::Neg:
            apply_unary(std::integral_constant<Op, Op::Neg>{});
            break;
        case Op::Abs:
            apply_unary(std::integral_constant<Op, Op::Abs>{});
            break;
        case Op::Sqrt:
            apply_unary(std::integral_constant<Op, Op::Sqrt>{});
            break;
        case Op::Sin:
            apply_unary(std::integral_constant<Op, Op::Sin>{});
            break;
        case Op::Cos:
            apply_unary(std::integral_constant<Op, Op::Cos>{});
            break;
        case Op::Exp:
            apply_unary(std::integral_constant<Op, Op::Exp>{});
            break;
        case Op::Log:
            apply_unary(std::integral_constant<Op, Op::Log>{});
            break;
        case Op::Clamp: {
            n -= 2;
            double* a = row(n - 1);
            const double *lo = row(n), *hi = row(n + 1);
            for (std::size_t i = 0; i < m; ++i) a[i] = std::min(std::max(a[i], lo[i]), hi[i]);
            break;
        }
        }
    }
    std::copy(stack, stack + m, out);
}

double SizingExpression::operator()(double x, double y, const Box& box) const {
    double stack[kMaxStack];
    double out;
    run(&x, &y, &out, 1, 1, stack, box);
    return out;
}

void SizingExpression::batched(const double* x, const double* y, double* out, std::size_t n, const Box& box,
                               const std::uint8_t* force, std::uint8_t* mask) const {
    constexpr std::size_t kBatch = 64;
    std::vector<double> stack(depth_ * kBatch);
    for (std::size_t first = 0; first < n; first += kBatch)
        run(x + first, y + first, out + first, std::min(kBatch, n - first), kBatch, stack.data(), box,
            force ? force + first : nullptr, mask ? mask + first : nullptr);
}

void SizingExpression::operator()(const double* x, const double* y, double* out, std::size_t n, const Box& box) const {
    batched(x, y, out, n, box, nullptr, nullptr);
}

void SizingExpression::taken(const double* x, const double* y, double* out, std::uint8_t* mask, std::size_t n,
                             const Box& box) const {
    batched(x, y, out, n, box, nullptr, mask);
}

void SizingExpression::forced(const double* x, const double* y, double* out, const std::uint8_t* mask, std::size_t n,
                              const Box& box) const {
    batched(x, y, out, n, box, mask, nullptr);
}

}  // namespace vrpd
