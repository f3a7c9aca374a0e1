// Point-file reading and writing (see vrpd/io.h).
#include "vrpd/io.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "shortest.h"

namespace vrpd {

namespace {

constexpr char kMagic[4] = {'V', 'R', 'P', 'D'};
constexpr std::uint32_t kVersion = 2;

bool ends_with(const std::string& s, const char* suffix) {
    std::size_t n = std::strlen(suffix);
    return s.size() >= n && s.compare(s.size() - n, n, suffix) == 0;
}

// Appends v's bytes, least significant first.
template <class T>
void put_le(std::string& out, T v) {
    char b[sizeof(T)];
    std::uint64_t bits = 0;
    std::memcpy(&bits, &v, sizeof(T));
    for (std::size_t i = 0; i < sizeof(T); ++i) b[i] = char(bits >> (8 * i));
    out.append(b, sizeof(T));
}

template <class T> T get_le(const unsigned char* b) {
    std::uint64_t bits = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i) bits |= std::uint64_t(b[i]) << (8 * i);
    T v;
    std::memcpy(&v, &bits, sizeof(T));
    return v;
}

// Rows to write: x, y, then named attribute columns.
struct Table {
    std::size_t rows = 0;
    std::vector<std::string> names;
    // x, y from a sampling's lattice or a set's points; then the attribute columns.
    const Sampling* sampling = nullptr;
    const std::vector<glm::dvec2>* points = nullptr;
    std::vector<const std::vector<double>*> attributes;
    // Row i's values (names.size() of them) into out.
    void row(std::size_t i, double* out) const {
        const glm::dvec2 p = sampling ? sampling->point(i) : (*points)[i];
        out[0] = p.x;
        out[1] = p.y;
        for (std::size_t k = 0; k < attributes.size(); ++k) out[k + 2] = (*attributes[k])[i];
    }
};

Table table_of(const Sampling& s) {
    Table t{s.size(), {"x", "y"}, &s, nullptr, {}};
    for (const auto& [name, values] : {std::pair{"t", &s.birth}, {"r", &s.local_radius}}) {
        if (values->empty()) continue;
        if (values->size() != s.size())
            throw Error(
                fmt::format("internal: column {} has {} values for {} samples", name, values->size(), s.size()));
        t.names.push_back(name);
        t.attributes.push_back(values);
    }
    return t;
}

Table table_of(const PointSet& set) {
    Table t{set.points.size(), {"x", "y"}, nullptr, &set.points, {}};
    for (std::size_t c = 0; c < set.columns.size(); ++c) {
        if (set.values[c].size() != set.points.size())
            throw Error(fmt::format("column {} has {} values for {} points", set.columns[c], set.values[c].size(),
                                    set.points.size()));
        t.names.push_back(set.columns[c]);
        t.attributes.push_back(&set.values[c]);
    }
    return t;
}

// Writes what buf holds once it passes a megabyte (the writers gather their rows in it).
void spill(std::string& buf, std::ostream& out) {
    if (buf.size() <= (1 << 20)) return;
    out.write(buf.data(), std::streamsize(buf.size()));
    buf.clear();
}

// The header, then the rows.
void write_bin(const Table& t, std::ostream& out) {
    std::string buf(kMagic, 4);
    put_le<std::uint32_t>(buf, kVersion);
    put_le<std::uint64_t>(buf, t.rows);
    put_le<std::uint32_t>(buf, std::uint32_t(t.names.size()));
    for (const std::string& name : t.names) {
        put_le<std::uint8_t>(buf, std::uint8_t(name.size()));
        buf += name;
    }
    std::vector<double> values(t.names.size());
    for (std::size_t i = 0; i < t.rows; ++i) {
        t.row(i, values.data());
        for (const double v : values) put_le<double>(buf, v);
        spill(buf, out);
    }
    out.write(buf.data(), std::streamsize(buf.size()));
}

// Moves the columns after x,y of `names` and `rows` (row-major, C a row) into a PointSet.
PointSet point_set(const std::string& path, const std::vector<std::string>& names, const std::vector<double>& rows) {
    const std::size_t c = names.size();
    PointSet set;
    set.points.resize(rows.size() / c);
    set.columns.assign(names.begin() + 2, names.end());
    set.values.assign(c - 2, std::vector<double>(set.points.size()));
    for (std::size_t i = 0; i < set.points.size(); ++i) {
        for (std::size_t k = 0; k < c; ++k)
            if (!std::isfinite(rows[i * c + k]))
                throw Error(fmt::format("{}: point {} has a value that is not finite ({})", path, i, names[k]));
        set.points[i] = {rows[i * c], rows[i * c + 1]};
        for (std::size_t k = 2; k < c; ++k) set.values[k - 2][i] = rows[i * c + k];
    }
    return set;
}

// A column list must start with x, y and name each column once, in letters, digits and '_'.
void check_columns(const std::string& where, const std::vector<std::string>& names) {
    if (names.size() < 2 || names[0] != "x" || names[1] != "y")
        throw Error(fmt::format("{}: the first two columns must be x,y", where));
    for (std::size_t k = 0; k < names.size(); ++k) {
        const std::string& n = names[k];
        const bool word = !n.empty() && std::all_of(n.begin(), n.end(), [](unsigned char ch) {
            return std::isalnum(ch) || ch == '_';
        });
        if (!word) throw Error(fmt::format("{}: column {} has no valid name (letters, digits, _)", where, k + 1));
        if (std::find(names.begin(), names.begin() + std::ptrdiff_t(k), n) != names.begin() + std::ptrdiff_t(k))
            throw Error(fmt::format("{}: column {} is named twice", where, n));
    }
}

PointSet read_bin(const std::string& path, const std::string& bytes) {
    const auto* b = reinterpret_cast<const unsigned char*>(bytes.data());
    if (bytes.size() < 16 || std::memcmp(b, kMagic, 4) != 0) throw Error(path + ": not a vrpd .bin file (bad header)");
    const std::uint32_t version = get_le<std::uint32_t>(b + 4);
    const std::uint64_t n = get_le<std::uint64_t>(b + 8);
    std::vector<std::string> names{"x", "y"};
    std::size_t at = 16;
    if (version == 2) {
        if (bytes.size() < 20) throw Error(path + ": .bin version 2 without its column count");
        const std::uint32_t c = get_le<std::uint32_t>(b + 16);
        at = 20;
        names.clear();
        for (std::uint32_t k = 0; k < c; ++k) {
            if (at >= bytes.size() || at + 1 + b[at] > bytes.size())
                throw Error(fmt::format("{}: .bin column list ends early (column {} of {})", path, k + 1, c));
            names.emplace_back(bytes.data() + at + 1, b[at]);
            at += 1 + b[at];
        }
        check_columns(path, names);
    } else if (version != 1) {
        throw Error(fmt::format("{}: unsupported .bin version {}", path, version));
    }
    const std::uint64_t row = 8 * names.size();
    if (n > (bytes.size() - at) / row || bytes.size() != at + row * n)
        throw Error(fmt::format("{}: .bin says {} points of {} columns but holds {} bytes", path, n, names.size(),
                                bytes.size()));
    std::vector<double> rows(n * names.size());
    for (std::size_t k = 0; k < rows.size(); ++k) rows[k] = get_le<double>(b + at + 8 * k);
    return point_set(path, names, rows);
}

std::vector<std::string> split_header(std::string_view row) {
    std::vector<std::string> names;
    std::size_t pos = 0;
    for (;;) {
        std::size_t comma = row.find(',', pos);
        std::string_view field = row.substr(pos, comma == std::string_view::npos ? comma : comma - pos);
        while (!field.empty() && field.front() == ' ') field.remove_prefix(1);
        while (!field.empty() && field.back() == ' ') field.remove_suffix(1);
        names.emplace_back(field);
        if (comma == std::string_view::npos) return names;
        pos = comma + 1;
    }
}

// A row as an error message shows it: cut to 60 characters, bytes other than printable ASCII as
// \xNN (a row of numbers is ASCII; a UTF-8 line separator would break the message's one line).
std::string shown_row(std::string_view row) {
    constexpr std::size_t kShown = 60;
    std::string out = "`";
    for (std::size_t i = 0; i < row.size() && i < kShown; ++i) {
        const unsigned char ch = (unsigned char)row[i];
        if (ch < 0x20 || ch >= 0x7f)
            out += fmt::format("\\x{:02x}", ch);
        else out += char(ch);
    }
    out += row.size() > kShown ? "`..." : "`";
    return out;
}

// A CSV row longer than this is not a point file's (a few numbers of at most 24 characters).
constexpr std::size_t kMaxLine = 4096;

PointSet read_csv(const std::string& path, std::string_view head, std::istream& in) {
    std::vector<std::string> names{"x", "y"};
    std::vector<double> rows;
    std::string expected = "two finite numbers `x,y`";
    std::size_t line = 0;
    auto parse = [&](std::string_view row) {
        ++line;
        if (line == 1 && row.starts_with("\xEF\xBB\xBF")) row.remove_prefix(3);  // a UTF-8 byte order mark
        if (!row.empty() && row.back() == '\r') row.remove_suffix(1);
        if (row.empty()) return;
        if (line == 1 && (std::isalpha((unsigned char)row.front()) || row.front() == '_')) {
            names = split_header(row);
            check_columns(fmt::format("{}:1", path), names);
            expected = fmt::format("{} finite numbers `{}`", names.size(), fmt::join(names, ","));
            return;
        }
        const auto wrong_columns = [&] {
            return Error(fmt::format("{}:{}: expected {} columns `{}`, got {}", path, line, names.size(),
                                     fmt::join(names, ","), shown_row(row)));
        };
        const char* p = row.data();
        const char* last = row.data() + row.size();
        for (std::size_t k = 0; k < names.size(); ++k) {
            while (p < last && *p == ' ') ++p;
            double v = 0;
            auto [next, ec] = std::from_chars(p, last, v);
            if (ec != std::errc() || !std::isfinite(v))
                throw Error(fmt::format("{}:{}: expected {}, got {}", path, line, expected, shown_row(row)));
            rows.push_back(v);
            p = next;
            while (p < last && *p == ' ') ++p;
            if (k + 1 < names.size()) {
                if (p == last || *p != ',') throw wrong_columns();
                ++p;
            }
        }
        if (p != last) throw wrong_columns();
    };
    // Read in chunks (`head` first), a line at a time, so that memory stays bounded by the rows,
    // not the bytes: a stream without newlines is refused at the line limit.
    std::string row;
    auto feed = [&](const char* p, const char* end) {
        while (p < end) {
            const char* nl = static_cast<const char*>(std::memchr(p, '\n', std::size_t(end - p)));
            row.append(p, nl ? nl : end);
            if (row.size() > kMaxLine)
                throw Error(fmt::format("{}:{}: a line longer than {} characters: {}", path, line + 1, kMaxLine,
                                        shown_row(row)));
            if (!nl) return;
            parse(row);
            row.clear();
            p = nl + 1;
        }
    };
    feed(head.data(), head.data() + head.size());
    std::vector<char> chunk(1 << 16);
    while (in.read(chunk.data(), std::streamsize(chunk.size())) || in.gcount() > 0)
        feed(chunk.data(), chunk.data() + in.gcount());
    if (in.bad()) throw Error(fmt::format("cannot read {}: {}", path, std::strerror(errno)));
    if (!row.empty()) parse(row);
    return point_set(path, names, rows);
}

// The error of a write that failed, with its reason.
Error write_error(const std::string& path, const std::string& why) {
    return Error(fmt::format("cannot write {}: {}", path, why));
}

// The temporary a write is going to, for remove_partial_file (a signal handler may read it).
char partial_file[4096];

// Where a write of `path` goes: directly to a device, FIFO or socket (never replaced), or through
// a temporary in the real directory of a regular file (links resolved, so a link keeps pointing
// at the new file).
struct Target {
    bool direct;
    std::filesystem::path file;  // the file to write directly, or to replace
};

Target target_of(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (fs::is_directory(st)) throw Error(path + ": is a directory");
    if (fs::exists(st) && !fs::is_regular_file(st)) return {true, path};
    const fs::path real = fs::weakly_canonical(fs::absolute(path), ec);
    if (ec) throw write_error(path, ec.message());
    return {false, real};
}

// Creates a temporary beside `file` (a short name: any name the file system takes will do).
std::string make_temporary(const std::filesystem::path& file, const std::string& path) {
    std::string name = (file.parent_path() / ".vrpd-XXXXXX").string();
    const int fd = ::mkstemp(name.data());
    if (fd < 0) throw write_error(path, std::strerror(errno));
    ::close(fd);
    return name;
}

void write_csv(const Table& t, std::ostream& out) {
    std::string buf;
    for (std::size_t k = 0; k < t.names.size(); ++k) {
        buf += k ? "," : "";
        buf += t.names[k];
    }
    buf += "\n";
    // A row: each number in at most 32 characters (write_shortest), a comma or newline after it.
    std::vector<char> row(t.names.size() * 33);
    std::vector<double> values(t.names.size());
    for (std::size_t i = 0; i < t.rows; ++i) {
        t.row(i, values.data());
        char* e = row.data();
        for (std::size_t k = 0; k < values.size(); ++k) {
            if (k) *e++ = ',';
            e = detail::write_shortest(e, values[k]);
        }
        *e++ = '\n';
        buf.append(row.data(), e);
        spill(buf, out);
    }
    out.write(buf.data(), std::streamsize(buf.size()));
}

}  // namespace

void check_writable(const std::string& path) {
    if (path == "-") return;
    const Target t = target_of(path);
    if (t.direct) {
        if (::access(t.file.c_str(), W_OK) != 0) throw write_error(path, std::strerror(errno));
        return;
    }
    std::error_code ignored;
    std::filesystem::remove(make_temporary(t.file, path), ignored);
}

namespace {

// Writes `s` to `path` as write_points describes.
void write_table(const Table& s, const std::string& path) {
    namespace fs = std::filesystem;
    if (path == "-") {
        write_csv(s, std::cout);
        if (!std::cout.flush()) throw write_error("standard output", std::strerror(errno));
        return;
    }
    const bool bin = ends_with(path, ".bin");
    const Target t = target_of(path);
    if (t.direct) {
        std::ofstream out(t.file, std::ios::binary);
        if (out) bin ? write_bin(s, out) : write_csv(s, out);
        if (!out.flush()) throw write_error(path, std::strerror(errno));
        return;
    }
    const std::string tmp = make_temporary(t.file, path);
    std::snprintf(partial_file, sizeof partial_file, "%s", tmp.c_str());
    auto fail = [&](const std::string& why) {
        std::error_code ignored;
        fs::remove(tmp, ignored);
        partial_file[0] = 0;
        throw write_error(path, why);
    };
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (out) bin ? write_bin(s, out) : write_csv(s, out);
        out.close();
        if (!out) fail(std::strerror(errno));
    }
    // mkstemp makes the file private; give it the mode a new file would have.
    const mode_t mask = ::umask(0);
    ::umask(mask);
    ::chmod(tmp.c_str(), 0666 & ~mask);
    std::error_code ec;
    fs::rename(tmp, t.file, ec);
    if (ec) fail(ec.message());
    partial_file[0] = 0;
}

}  // namespace

void write_points(const Sampling& s, const std::string& path) { write_table(table_of(s), path); }

void write_point_set(const PointSet& set, const std::string& path) { write_table(table_of(set), path); }

void write_csv(const Sampling& s, std::ostream& out) { write_csv(table_of(s), out); }

void write_csv(const PointSet& set, std::ostream& out) { write_csv(table_of(set), out); }

void remove_partial_file() noexcept {
    if (partial_file[0] != 0) ::unlink(partial_file);
}

PointSet read_point_set(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw Error(path + ": is a directory");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(fmt::format("cannot read {}: {}", path, std::strerror(errno)));
    char magic[4] = {};
    in.read(magic, 4);
    const std::streamsize got = in.gcount();
    if (got == 4 && std::memcmp(magic, kMagic, 4) == 0) {
        std::string bytes(magic, 4);
        bytes.append(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
        return read_bin(path, bytes);
    }
    return read_csv(path, std::string_view(magic, std::size_t(got)), in);  // those bytes start the CSV
}

PointSet parse_point_set(std::string_view bytes, const std::string& name) {
    if (bytes.size() >= 4 && std::memcmp(bytes.data(), kMagic, 4) == 0) return read_bin(name, std::string(bytes));
    std::istringstream none;
    return read_csv(name, bytes, none);
}

std::vector<glm::dvec2> read_points(const std::string& path) { return read_point_set(path).points; }

const std::vector<double>* PointSet::column(std::string_view name) const {
    for (std::size_t k = 0; k < columns.size(); ++k)
        if (columns[k] == name) return &values[k];
    return nullptr;
}

}  // namespace vrpd
