// Point-file reading and writing (see vrpd/io.h).
#include "vrpd/io.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

namespace vrpd {
namespace {

constexpr char kMagic[4] = {'V', 'R', 'P', 'D'};
constexpr std::uint32_t kVersion = 1;

bool ends_with(const std::string& s, const char* suffix) {
    std::size_t n = std::strlen(suffix);
    return s.size() >= n && s.compare(s.size() - n, n, suffix) == 0;
}

template <class T> void put_le(std::ostream& out, T v) {
    unsigned char b[sizeof(T)];
    std::uint64_t bits = 0;
    std::memcpy(&bits, &v, sizeof(T));
    for (std::size_t i = 0; i < sizeof(T); ++i) b[i] = (unsigned char)(bits >> (8 * i));
    out.write(reinterpret_cast<const char*>(b), sizeof(T));
}

template <class T> T get_le(const unsigned char* b) {
    std::uint64_t bits = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i) bits |= std::uint64_t(b[i]) << (8 * i);
    T v;
    std::memcpy(&v, &bits, sizeof(T));
    return v;
}

void write_bin(const Sampling& s, std::ostream& out) {
    out.write(kMagic, 4);
    put_le<std::uint32_t>(out, kVersion);
    put_le<std::uint64_t>(out, s.size());
    for (std::size_t i = 0; i < s.size(); ++i) {
        glm::dvec2 p = s.point(i);
        put_le<double>(out, p.x);
        put_le<double>(out, p.y);
    }
}

std::vector<glm::dvec2> read_bin(const std::string& path, const std::string& bytes) {
    const auto* b = reinterpret_cast<const unsigned char*>(bytes.data());
    if (bytes.size() < 16 || std::memcmp(b, kMagic, 4) != 0) throw Error(path + ": not a vrpd .bin file (bad header)");
    if (get_le<std::uint32_t>(b + 4) != kVersion) throw Error(path + ": unsupported .bin version");
    std::uint64_t n = get_le<std::uint64_t>(b + 8);
    if (n > (bytes.size() - 16) / 16 || bytes.size() != 16 + 16 * n)
        throw Error(fmt::format("{}: .bin says {} points but holds {} bytes", path, n, bytes.size()));
    std::vector<glm::dvec2> pts(n);
    for (std::uint64_t i = 0; i < n; ++i) {
        pts[i] = {get_le<double>(b + 16 + 16 * i), get_le<double>(b + 24 + 16 * i)};
        if (!std::isfinite(pts[i].x) || !std::isfinite(pts[i].y))
            throw Error(fmt::format("{}: point {} is not finite", path, i));
    }
    return pts;
}

std::vector<glm::dvec2> read_csv(const std::string& path, const std::string& text) {
    std::vector<glm::dvec2> pts;
    std::size_t pos = 0, line = 0;
    while (pos < text.size()) {
        std::size_t end = text.find('\n', pos);
        if (end == std::string::npos) end = text.size();
        std::string_view row(text.data() + pos, end - pos);
        pos = end + 1;
        ++line;
        if (!row.empty() && row.back() == '\r') row.remove_suffix(1);
        if (row.empty()) continue;
        if (line == 1 && (row == "x,y" || row == "x, y")) continue;
        double v[2];
        const char* p = row.data();
        const char* last = row.data() + row.size();
        for (int k = 0; k < 2; ++k) {
            while (p < last && *p == ' ') ++p;
            auto [next, ec] = std::from_chars(p, last, v[k]);
            if (ec != std::errc() || !std::isfinite(v[k]))
                throw Error(fmt::format("{}:{}: expected two finite numbers `x,y`, got `{}`", path, line, row));
            p = next;
            while (p < last && *p == ' ') ++p;
            if (k == 0) {
                if (p == last || *p != ',')
                    throw Error(fmt::format("{}:{}: expected two columns `x,y`, got `{}`", path, line, row));
                ++p;
            }
        }
        if (p != last) throw Error(fmt::format("{}:{}: expected two columns `x,y`, got `{}`", path, line, row));
        pts.push_back({v[0], v[1]});
    }
    return pts;
}

std::filesystem::path partial_path(const std::string& path) {
    const std::filesystem::path target(path);
    if (std::filesystem::is_directory(target)) throw Error(path + ": is a directory");
    std::string name = ".";
    name += target.filename().string();
    name += ".partial";
    return target.parent_path() / name;
}

}  // namespace

void write_csv(const Sampling& s, std::ostream& out) {
    std::string buf = "x,y\n";
    char num[64];
    for (std::size_t i = 0; i < s.size(); ++i) {
        glm::dvec2 p = s.point(i);
        char* e = std::to_chars(num, num + sizeof num, p.x).ptr;
        *e++ = ',';
        e = std::to_chars(e, num + sizeof num, p.y).ptr;
        *e++ = '\n';
        buf.append(num, e);
        if (buf.size() > (1 << 20)) {
            out.write(buf.data(), std::streamsize(buf.size()));
            buf.clear();
        }
    }
    out.write(buf.data(), std::streamsize(buf.size()));
}

void check_writable(const std::string& path) {
    const std::filesystem::path tmp = partial_path(path);
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) throw Error(fmt::format("cannot write {}: {}", path, std::strerror(errno)));
    }
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
}

void write_points(const Sampling& s, const std::string& path) {
    namespace fs = std::filesystem;
    const fs::path target(path);
    const fs::path tmp = partial_path(path);
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) throw Error(fmt::format("cannot write {}: {}", path, std::strerror(errno)));
        if (ends_with(path, ".bin")) write_bin(s, out);
        else write_csv(s, out);
        out.flush();
        if (!out) {
            std::error_code ignored;
            fs::remove(tmp, ignored);
            throw Error(fmt::format("cannot write {}: {}", path, std::strerror(errno)));
        }
    }
    std::error_code ec;
    fs::rename(tmp, target, ec);
    if (ec) {
        fs::remove(tmp, ec);
        throw Error(fmt::format("cannot write {}: {}", path, ec.message()));
    }
}

std::vector<glm::dvec2> read_points(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw Error(path + ": is a directory");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(fmt::format("cannot read {}: {}", path, std::strerror(errno)));
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (bytes.size() >= 4 && std::memcmp(bytes.data(), kMagic, 4) == 0) return read_bin(path, bytes);
    return read_csv(path, bytes);
}

}  // namespace vrpd
