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

#include <fmt/format.h>

namespace vrpd {
namespace {

using Op = SizingExpression::Op;
using Step = SizingExpression::Step;

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

SizingExpression::SizingExpression(std::string text) : text_(std::move(text)), program_(Parser(text_).parse()) {
    // The stack depth the program reaches: a value pushes one, an operator pops its arity less one.
    std::size_t depth = 0;
    for (const Step& s : program_) {
        if (s.op <= Op::H) {
            ++depth;  // Number and the variables
        } else if (s.op <= Op::Pow || s.op == Op::Min || s.op == Op::Max) {
            --depth;  // binary operators
        } else if (s.op == Op::Clamp) {
            depth -= 2;
        }
        depth_ = std::max(depth_, depth);
    }
    if (depth_ > kMaxStack) throw Error("sizing expression: too deeply nested to evaluate");
}

// Runs the program over m <= stride points: stack entry k of point i is stack[k * stride + i].
// Each step runs over all the points before the next, so its dispatch is paid once per batch;
// every point's arithmetic is the scalar evaluation's, in the same order.
void SizingExpression::run(const double* x, const double* y, double* out, std::size_t m, std::size_t stride,
                           double* stack, const Box& box) const {
    std::size_t n = 0;  // entries on the stack
    auto row = [&](std::size_t k) { return stack + k * stride; };
    auto binary = [&](auto op) {
        --n;
        double* a = row(n - 1);
        const double* b = row(n);
        for (std::size_t i = 0; i < m; ++i) a[i] = op(a[i], b[i]);
    };
    auto unary = [&](auto op) {
        double* a = row(n - 1);
        for (std::size_t i = 0; i < m; ++i) a[i] = op(a[i]);
    };
    auto push = [&](auto value) {
        double* a = row(n++);
        for (std::size_t i = 0; i < m; ++i) a[i] = value(i);
    };
    for (const Step& s : program_) {
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
        case Op::Add: binary([](double a, double b) { return a + b; }); break;
        case Op::Sub: binary([](double a, double b) { return a - b; }); break;
        case Op::Mul: binary([](double a, double b) { return a * b; }); break;
        case Op::Div: binary([](double a, double b) { return a / b; }); break;
        case Op::Pow: binary([](double a, double b) { return std::pow(a, b); }); break;
        case Op::Min: binary([](double a, double b) { return std::min(a, b); }); break;
        case Op::Max: binary([](double a, double b) { return std::max(a, b); }); break;
        case Op::Neg: unary([](double a) { return -a; }); break;
        case Op::Abs: unary([](double a) { return std::abs(a); }); break;
        case Op::Sqrt: unary([](double a) { return std::sqrt(a); }); break;
        case Op::Sin: unary([](double a) { return std::sin(a); }); break;
        case Op::Cos: unary([](double a) { return std::cos(a); }); break;
        case Op::Exp: unary([](double a) { return std::exp(a); }); break;
        case Op::Log: unary([](double a) { return std::log(a); }); break;
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

void SizingExpression::operator()(const double* x, const double* y, double* out, std::size_t n,
                                  const Box& box) const {
    constexpr std::size_t kBatch = 64;
    std::vector<double> stack(depth_ * kBatch);
    for (std::size_t first = 0; first < n; first += kBatch)
        run(x + first, y + first, out + first, std::min(kBatch, n - first), kBatch, stack.data(), box);
}

SizingRule parse_sizing_rule(const std::string& name) {
    if (name == "prior") return SizingRule::Prior;
    if (name == "current") return SizingRule::Current;
    if (name == "bigger") return SizingRule::Bigger;
    if (name == "smaller") return SizingRule::Smaller;
    throw Error(fmt::format("unknown rule '{}': use prior, current, bigger or smaller", name));
}

const char* sizing_rule_name(SizingRule rule) {
    switch (rule) {
    case SizingRule::Prior: return "prior";
    case SizingRule::Current: return "current";
    case SizingRule::Bigger: return "bigger";
    case SizingRule::Smaller: return "smaller";
    }
    return "?";
}

double rule_radius(SizingRule rule, double r_earlier, double r_later) {
    switch (rule) {
    case SizingRule::Prior: return r_earlier;
    case SizingRule::Current: return r_later;
    case SizingRule::Bigger: return std::max(r_earlier, r_later);
    case SizingRule::Smaller: return std::min(r_earlier, r_later);
    }
    return r_earlier;
}

}  // namespace vrpd
