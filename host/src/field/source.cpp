// A sizing field's source (field/table.h): an expression, or a greyscale image decoded by stb_image
// (Debian's libstb, a maintained decoder of PNG and binary PGM among others).
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

#include <fmt/format.h>
#include <stb_image.h>

#include "table.h"
#include "vrpd/sizing.h"

namespace vrpd::detail {
namespace {

constexpr int kMaxImageSide = 16384;

// Grey levels in [0, 1], row 0 at the top of the box (y = height), as the image is seen.
struct GreyImage {
    int width = 0, height = 0;
    std::vector<float> grey;

    // Bilinear between pixel centres, constant past the outer half pixel.
    double at(double u, double v) const {
        const double fx = std::clamp(u * width - 0.5, 0.0, double(width - 1));
        const double fy = std::clamp((1.0 - v) * height - 0.5, 0.0, double(height - 1));
        const int x0 = int(fx), y0 = int(fy);
        const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
        const double tx = fx - x0, ty = fy - y0;
        auto g = [&](int x, int y) { return double(grey[std::size_t(y) * std::size_t(width) + std::size_t(x)]); };
        return (g(x0, y0) * (1 - tx) + g(x1, y0) * tx) * (1 - ty) + (g(x0, y1) * (1 - tx) + g(x1, y1) * tx) * ty;
    }
};

// stb_image's reason for its last failure; stb names an unknown PNG chunk by its type's bytes,
// which are empty at a file's premature end.
std::string failure_reason() {
    const char* why = stbi_failure_reason();
    if (!why || !std::isprint(static_cast<unsigned char>(why[0]))) return "corrupt or truncated data";
    return why;
}

// Throws Error if a binary PGM (P5) file ends before its pixels do: stb_image reads such a file's
// pixels without checking that they are all there. The header is stb's grammar: the magic, then
// width, height and largest value, each after whitespace and # comments, and one byte of
// whitespace before the pixels (2 bytes each past a largest value of 255).
void check_pgm_length(std::FILE* file, const std::string& path) {
    std::rewind(file);
    int c = std::fgetc(file);
    if (c != 'P' || std::fgetc(file) != '5') {
        std::rewind(file);
        return;
    }
    std::uint64_t field[3] = {};
    c = std::fgetc(file);
    for (std::uint64_t& v : field) {
        for (;;) {
            while (c != EOF && std::isspace(c)) c = std::fgetc(file);
            if (c != '#') break;
            while (c != EOF && c != '\n' && c != '\r') c = std::fgetc(file);
        }
        while (c != EOF && std::isdigit(c) && v < (std::uint64_t(1) << 32)) {
            v = v * 10 + std::uint64_t(c - '0');
            c = std::fgetc(file);
        }
    }
    // c is the byte after the largest value's digits: the pixels start after it.
    const long pixels_at = std::ftell(file);
    std::fseek(file, 0, SEEK_END);
    const long end = std::ftell(file);
    std::rewind(file);
    const std::uint64_t need = field[0] * field[1] * (field[2] > 255 ? 2 : 1);
    if (pixels_at >= 0 && end >= pixels_at && std::uint64_t(end - pixels_at) < need)
        throw Error(fmt::format("the sizing image {} is truncated: its {} x {} pixels need {} bytes, it holds {}", path,
                                field[0], field[1], need, end - pixels_at));
}

// Fills img.grey from decoded pixels of `n` channels, full scale `scale`: the first channel. A
// colour image (n >= 3, palette images among them) is a grey one if every pixel has red = green =
// blue, as many tools store grey; else Error names the first pixel that does not. Alpha is ignored.
template <typename T>
void take_grey(const T* px, int n, float scale, GreyImage& img, const std::string& path) {
    for (std::size_t i = 0; i < img.grey.size(); ++i) {
        const T* p = px + i * std::size_t(n);
        if (n >= 3 && (p[0] != p[1] || p[1] != p[2]))
            throw Error(
                fmt::format("the sizing image {} is not greyscale: its pixel ({}, {}) is red {}, green {}, "
                            "blue {}",
                            path, i % std::size_t(img.width), i / std::size_t(img.width), unsigned(p[0]),
                            unsigned(p[1]), unsigned(p[2])));
        img.grey[i] = float(p[0]) / scale;
    }
}

GreyImage load_grey(const std::string& path) {
    std::FILE* file = std::fopen(path.c_str(), "rb");
    if (!file) throw Error(fmt::format("cannot read the sizing image {}: {}", path, std::strerror(errno)));
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> closer(file, &std::fclose);
    int w = 0, h = 0, channels = 0;
    if (!stbi_info_from_file(file, &w, &h, &channels))
        throw Error(fmt::format("the sizing image {} is not a PNG or binary PGM image stb_image can decode ({})", path,
                                failure_reason()));
    if (w > kMaxImageSide || h > kMaxImageSide)
        throw Error(
            fmt::format("the sizing image {} is {} x {} pixels; at most {} per side", path, w, h, kMaxImageSide));
    GreyImage img;
    img.width = w;
    img.height = h;
    check_pgm_length(file, path);
    img.grey.resize(std::size_t(w) * std::size_t(h));
    // Grey (with or without alpha) decodes to one channel; colour keeps its channels to be checked.
    const int want = channels >= 3 ? channels : 1;
    int cw = 0, ch = 0, cc = 0;
    if (stbi_is_16_bit_from_file(file)) {
        std::unique_ptr<stbi_us, void (*)(void*)> px(stbi_load_from_file_16(file, &cw, &ch, &cc, want),
                                                     &stbi_image_free);
        if (!px) throw Error(fmt::format("cannot decode the sizing image {}: {}", path, failure_reason()));
        take_grey(px.get(), want, 65535.0f, img, path);
    } else {
        std::unique_ptr<stbi_uc, void (*)(void*)> px(stbi_load_from_file(file, &cw, &ch, &cc, want), &stbi_image_free);
        if (!px) throw Error(fmt::format("cannot decode the sizing image {}: {}", path, failure_reason()));
        take_grey(px.get(), want, 255.0f, img, path);
    }
    return img;
}

}  // namespace

FieldSource field_source(const Sizing& s, const Box& box) {
    if (s.expression.empty() == s.image.empty())
        throw Error("a sizing field is an expression or an image, one of them");
    if (!s.expression.empty()) {
        auto expr = std::make_shared<SizingExpression>(s.expression);
        return
            [expr, box](const double* x, const double* y, double* out, std::size_t n) { (*expr)(x, y, out, n, box); };
    }
    if (!(std::isfinite(s.r_min) && std::isfinite(s.r_max) && s.r_min > 0 && s.r_min <= s.r_max))
        throw Error(
            fmt::format("an image's radii need 0 < r_min <= r_max, finite (got r_min {}, r_max {})", s.r_min, s.r_max));
    auto img = std::make_shared<GreyImage>(load_grey(s.image));
    const double lo = s.r_min, span = s.r_max - s.r_min;
    return [img, box, lo, span](const double* x, const double* y, double* out, std::size_t n) {
        for (std::size_t i = 0; i < n; ++i) out[i] = lo + span * img->at(x[i] / box.width, y[i] / box.height);
    };
}

FieldBranches field_branches(const Sizing& s, const Box& box) {
    if (s.expression.empty()) return {};
    auto expr = std::make_shared<SizingExpression>(s.expression);
    if (!expr->kinked()) return {};
    return {[expr, box](const double* x, const double* y, double* out, std::uint8_t* mask, std::size_t n) {
                expr->taken(x, y, out, mask, n, box);
            },
            [expr, box](const double* x, const double* y, double* out, const std::uint8_t* mask, std::size_t n) {
                expr->forced(x, y, out, mask, n, box);
            }};
}

}  // namespace vrpd::detail
