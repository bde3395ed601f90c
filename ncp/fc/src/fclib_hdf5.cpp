#include "fclib_hdf5.hpp"

#include <hdf5.h>

#include <climits>
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <utility>

namespace ncp::fc::internal {

namespace {

/// Longest info string accepted (a corrupted type size must not become a huge
/// allocation).
constexpr size_t kMaxStringBytes = size_t{1} << 20;

/// Widest integer or floating-point element accepted (HDF5 converts up to 128-bit types).
constexpr size_t kMaxNumberBytes = 16;

/// Debian's serial HDF5 is built without thread safety: one file at a time.
std::mutex& Hdf5Mutex() {
  static std::mutex mutex;
  return mutex;
}

/// Owner of one HDF5 identifier, released with its own close function.
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& other) noexcept : id_(other.id_), close_(other.close_) {
    other.id_ = -1;
  }
  Handle& operator=(Handle&&) = delete;
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  bool valid() const { return id_ >= 0; }
  hid_t get() const { return id_; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

/// HDF5's automatic error printing off while alive; the previous handler restored after.
class QuietHdf5 {
 public:
  QuietHdf5() {
    if (H5Eget_auto2(H5E_DEFAULT, &func_, &data_) < 0) func_ = nullptr;
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  QuietHdf5(const QuietHdf5&) = delete;
  QuietHdf5& operator=(const QuietHdf5&) = delete;
  ~QuietHdf5() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }

 private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

std::string Str(long long v) { return std::to_string(v); }

/// One open FCLIB file: typed, size-checked reads of its datasets, and errors that name
/// the file and the dataset.
class FclibFile {
 public:
  explicit FclibFile(const std::string& path)
      : lock_(Hdf5Mutex()), path_(path), file_(Open(path), H5Fclose) {}

  [[noreturn]] void Fail(const std::string& object, const std::string& defect) const {
    throw std::runtime_error("'" + path_ + "': " + object + ": " + defect);
  }

  /// Whether every component of the absolute path exists (H5Lexists fails, rather than
  /// answering false, when a parent is missing).
  bool Exists(const std::string& object) const {
    for (size_t end = object.find('/', 1);; end = object.find('/', end + 1)) {
      const std::string prefix = object.substr(0, end);
      if (H5Lexists(file_.get(), prefix.c_str(), H5P_DEFAULT) <= 0) return false;
      if (end == std::string::npos) return true;
    }
  }

  void RequireGroup(const std::string& group) const {
    if (!Exists(group)) Fail(group, "missing (required group)");
    const Handle g(H5Gopen2(file_.get(), group.c_str(), H5P_DEFAULT), H5Gclose);
    if (!g.valid()) Fail(group, "exists but cannot be opened as a group");
  }

  /// An integer stored as a 1-element dataset or a scalar, in [min_value, INT_MAX].
  int ReadInt(const std::string& name, long long min_value) const {
    const std::vector<long long> v = ReadIntegers(name, 1);
    if (v[0] < min_value || v[0] > INT_MAX)
      Fail(name, "value " + Str(v[0]) + " outside [" + Str(min_value) + ", " +
                     Str(INT_MAX) + "]");
    return static_cast<int>(v[0]);
  }

  /// An integer array of exactly `length` entries, each in [0, INT_MAX].
  std::vector<int> ReadIndexArray(const std::string& name, long long length) const {
    const std::vector<long long> v = ReadIntegers(name, length);
    std::vector<int> out(v.size());
    for (size_t k = 0; k < v.size(); ++k) {
      if (v[k] < 0 || v[k] > INT_MAX)
        Fail(name + "[" + Str(static_cast<long long>(k)) + "]",
             "value " + Str(v[k]) + " outside [0, " + Str(INT_MAX) + "]");
      out[k] = static_cast<int>(v[k]);
    }
    return out;
  }

  /// A floating-point array of exactly `length` entries (all entries finite when
  /// `require_finite`; an FCLIB compressed matrix may leave unused entries undefined).
  Vector ReadDoubles(const std::string& name, long long length,
                     bool require_finite = true) const {
    const Handle ds = OpenDataset(name, H5T_FLOAT, "floating point");
    CheckLength(ds, name, length);
    Vector v(length);
    if (length > 0 &&
        H5Dread(ds.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0)
      Fail(name, "HDF5 could not read the data (file corrupted?)");
    if (require_finite)
      for (Eigen::Index k = 0; k < v.size(); ++k)
        if (!std::isfinite(v[k]))
          Fail(name + "[" + Str(k) + "]",
               "not a finite number (" + std::to_string(v[k]) + ")");
    return v;
  }

  /// A string dataset (fixed or variable length, one element); std::nullopt when absent.
  std::optional<std::string> ReadOptionalString(const std::string& name) const {
    if (!Exists(name)) return std::nullopt;
    const Handle ds = OpenDataset(name, H5T_STRING, "string");
    CheckLength(ds, name, 1);
    const Handle file_type(H5Dget_type(ds.get()), H5Tclose);
    const htri_t variable = H5Tis_variable_str(file_type.get());
    const Handle memory_type(H5Tcopy(H5T_C_S1), H5Tclose);
    if (variable < 0 || !memory_type.valid()) Fail(name, "unreadable string type");
    if (variable > 0) {
      if (H5Tset_size(memory_type.get(), H5T_VARIABLE) < 0)
        Fail(name, "unreadable string type");
      char* text = nullptr;
      if (H5Dread(ds.get(), memory_type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &text) < 0)
        Fail(name, "HDF5 could not read the string (file corrupted?)");
      std::string out = text ? std::string(text) : std::string();
      const Handle space(H5Dget_space(ds.get()), H5Sclose);
      H5Dvlen_reclaim(memory_type.get(), space.get(), H5P_DEFAULT, &text);
      if (out.size() > kMaxStringBytes) Fail(name, "string longer than 1 MiB");
      return out;
    }
    const size_t size = H5Tget_size(file_type.get());
    if (size == 0 || size > kMaxStringBytes)
      Fail(name, "string size " + Str(static_cast<long long>(size)) +
                     " bytes outside [1, 1 MiB]");
    std::string buffer(size + 1, '\0');
    if (H5Tset_size(memory_type.get(), size + 1) < 0 ||
        H5Tset_strpad(memory_type.get(), H5T_STR_NULLTERM) < 0 ||
        H5Dread(ds.get(), memory_type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &buffer[0]) <
            0)
      Fail(name, "HDF5 could not read the string (file corrupted?)");
    return std::string(buffer.c_str());
  }

  /// An FCLIB matrix group, checked as described in fclib_hdf5.hpp.
  FclibMatrix ReadMatrix(const std::string& group) const {
    RequireGroup(group);
    FclibMatrix a;
    a.rows = ReadInt(group + "/m", 0);
    a.cols = ReadInt(group + "/n", 0);
    a.nzmax = ReadInt(group + "/nzmax", 0);
    a.nz = ReadInt(group + "/nz", -2);
    if (a.nz >= 0)
      ReadTriplets(group, &a);
    else
      ReadCompressed(group, &a);
    return a;
  }

 private:
  static hid_t Open(const std::string& path) {
    const htri_t is_hdf5 = H5Fis_hdf5(path.c_str());
    if (is_hdf5 < 0) throw std::runtime_error("'" + path + "': cannot open the file");
    if (is_hdf5 == 0) throw std::runtime_error("'" + path + "': not an HDF5 file");
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    if (file < 0)
      throw std::runtime_error("'" + path +
                               "': HDF5 could not open the file (corrupted?)");
    return file;
  }

  Handle OpenDataset(const std::string& name, H5T_class_t type_class,
                     const char* type_name) const {
    if (!Exists(name)) Fail(name, "missing (required dataset)");
    Handle ds(H5Dopen2(file_.get(), name.c_str(), H5P_DEFAULT), H5Dclose);
    if (!ds.valid()) Fail(name, "exists but cannot be opened as a dataset");
    const Handle type(H5Dget_type(ds.get()), H5Tclose);
    const H5T_class_t actual = type.valid() ? H5Tget_class(type.get()) : H5T_NO_CLASS;
    if (actual != type_class)
      Fail(name, std::string("has type class ") + ClassName(actual) + ", expected " +
                     type_name);
    // A corrupted element size makes HDF5 allocate size x length bytes to convert.
    const size_t size = H5Tget_size(type.get());
    if (type_class != H5T_STRING && (size == 0 || size > kMaxNumberBytes))
      Fail(name, "element size " + Str(static_cast<long long>(size)) +
                     " bytes, expected 1 to " +
                     Str(static_cast<long long>(kMaxNumberBytes)));
    return ds;
  }

  /// Scalars count as one element; arrays must have rank 1.
  void CheckLength(const Handle& ds, const std::string& name, long long length) const {
    const Handle space(H5Dget_space(ds.get()), H5Sclose);
    if (!space.valid()) Fail(name, "unreadable dataspace");
    const H5S_class_t kind = H5Sget_simple_extent_type(space.get());
    long long count = -1;
    if (kind == H5S_SCALAR) {
      count = 1;
    } else if (kind == H5S_NULL) {
      count = 0;
    } else if (kind == H5S_SIMPLE) {
      const int rank = H5Sget_simple_extent_ndims(space.get());
      if (rank != 1) Fail(name, "rank " + Str(rank) + ", expected a 1-D array");
      hsize_t dims[1] = {0};
      if (H5Sget_simple_extent_dims(space.get(), dims, nullptr) < 0)
        Fail(name, "unreadable dimensions");
      count = dims[0] > static_cast<hsize_t>(LLONG_MAX) ? -1
                                                        : static_cast<long long>(dims[0]);
    }
    if (count != length)
      Fail(name, "has " + (count < 0 ? std::string("an invalid number of") : Str(count)) +
                     " entries, expected " + Str(length));
  }

  std::vector<long long> ReadIntegers(const std::string& name, long long length) const {
    const Handle ds = OpenDataset(name, H5T_INTEGER, "integer");
    CheckLength(ds, name, length);
    std::vector<long long> v(static_cast<size_t>(length));
    if (length > 0 &&
        H5Dread(ds.get(), H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0)
      Fail(name, "HDF5 could not read the data (file corrupted?)");
    return v;
  }

  /// Every index[k] in [0, bound).
  void CheckIndices(const std::string& name, const std::vector<int>& index,
                    long long count, int bound, const char* meaning) const {
    for (long long k = 0; k < count; ++k)
      if (index[k] >= bound)
        Fail(name + "[" + Str(k) + "]", "= " + Str(index[k]) + " is not a valid " +
                                            meaning + " (expected 0 to " +
                                            Str(bound - 1) + ")");
  }

  void CheckFinite(const std::string& name, const std::vector<double>& x,
                   long long count) const {
    for (long long k = 0; k < count; ++k)
      if (!std::isfinite(x[k]))
        Fail(name + "[" + Str(k) + "]",
             "not a finite number (" + std::to_string(x[k]) + ")");
  }

  static std::vector<double> ToStd(const Vector& v) {
    return {v.data(), v.data() + v.size()};
  }

  void ReadTriplets(const std::string& group, FclibMatrix* a) const {
    a->i = ReadIndexArray(group + "/i", a->nz);
    a->p = ReadIndexArray(group + "/p", a->nz);
    a->x = ToStd(ReadDoubles(group + "/x", a->nz));
    CheckIndices(group + "/i", a->i, a->nz, a->rows, "row index (triplet form)");
    CheckIndices(group + "/p", a->p, a->nz, a->cols, "column index (triplet form)");
  }

  void ReadCompressed(const std::string& group, FclibMatrix* a) const {
    const bool by_columns = a->nz == -1;
    const int outer = by_columns ? a->cols : a->rows;
    const int inner = by_columns ? a->rows : a->cols;
    const char* form = by_columns ? "compressed columns" : "compressed rows";
    a->p = ReadIndexArray(group + "/p", static_cast<long long>(outer) + 1);
    if (a->p[0] != 0)
      Fail(group + "/p[0]", "= " + Str(a->p[0]) + ", expected 0 (" + form + ")");
    for (int k = 0; k < outer; ++k)
      if (a->p[k + 1] < a->p[k])
        Fail(group + "/p[" + Str(k + 1) + "]",
             "= " + Str(a->p[k + 1]) + " is less than p[" + Str(k) +
                 "] = " + Str(a->p[k]) + " (pointers must not decrease, " + form + ")");
    const int used = a->p[outer];
    if (used > a->nzmax)
      Fail(group + "/p[" + Str(outer) + "]",
           "= " + Str(used) + " entries exceed nzmax = " + Str(a->nzmax) + " (" + form +
               ")");
    a->i = ReadIndexArray(group + "/i", a->nzmax);
    const Vector x = ReadDoubles(group + "/x", a->nzmax, /*require_finite=*/false);
    a->x = ToStd(x);
    CheckIndices(
        group + "/i", a->i, used, inner,
        by_columns ? "row index (compressed columns)" : "column index (compressed rows)");
    CheckFinite(group + "/x", a->x, used);
  }

  static const char* ClassName(H5T_class_t c) {
    switch (c) {
      case H5T_INTEGER:
        return "integer";
      case H5T_FLOAT:
        return "floating point";
      case H5T_STRING:
        return "string";
      case H5T_COMPOUND:
        return "compound";
      case H5T_ARRAY:
        return "array";
      case H5T_ENUM:
        return "enum";
      case H5T_VLEN:
        return "variable length";
      case H5T_OPAQUE:
        return "opaque";
      case H5T_BITFIELD:
        return "bitfield";
      case H5T_REFERENCE:
        return "reference";
      case H5T_TIME:
        return "time";
      default:
        return "unknown";
    }
  }

  std::lock_guard<std::mutex> lock_;  // first: held while the file is open
  QuietHdf5 quiet_;
  std::string path_;
  Handle file_;
};

/// spacedim: the number of components per contact, 2 or 3.
int ReadSpacedim(const FclibFile& file, const std::string& root) {
  const int d = file.ReadInt(root + "/spacedim", 0);
  if (d != 2 && d != 3)
    file.Fail(root + "/spacedim", "= " + Str(d) + ", expected 2 or 3");
  return d;
}

/// A friction coefficient per contact: n_c finite entries, each >= 0.
Vector ReadMu(const FclibFile& file, const std::string& name, int num_contacts) {
  Vector mu = file.ReadDoubles(name, num_contacts);
  for (int a = 0; a < num_contacts; ++a)
    if (mu[a] < 0.0)
      file.Fail(name + "[" + Str(a) + "]",
                "= " + std::to_string(mu[a]) + " is negative (mu >= 0)");
  return mu;
}

std::string Shape(const FclibMatrix& a) { return Str(a.rows) + " x " + Str(a.cols); }

std::optional<FclibInfo> ReadInfo(const FclibFile& file, const std::string& root) {
  const std::string group = root + "/info";
  if (!file.Exists(group)) return std::nullopt;
  file.RequireGroup(group);
  FclibInfo info;
  info.title = file.ReadOptionalString(group + "/title");
  info.description = file.ReadOptionalString(group + "/description");
  info.math_info = file.ReadOptionalString(group + "/math_info");
  return info;
}

FclibKind Kind(const FclibFile& file) {
  if (file.Exists("/fclib_local")) return FclibKind::kLocal;
  if (file.Exists("/fclib_global")) return FclibKind::kGlobal;
  if (file.Exists("/fclib_global_rolling")) return FclibKind::kGlobalRolling;
  return FclibKind::kNone;
}

FclibLocal ReadLocal(const FclibFile& file) {
  const std::string root = "/fclib_local";
  file.RequireGroup(root);
  FclibLocal local;
  local.spacedim = ReadSpacedim(file, root);
  local.W = file.ReadMatrix(root + "/W");
  const int m = local.W.rows;
  if (local.W.cols != m || m % local.spacedim != 0)
    file.Fail(root + "/W", "is " + Shape(local.W) +
                               ", expected square with a size that " +
                               "is a multiple of spacedim = " + Str(local.spacedim));
  if (file.Exists(root + "/V") != file.Exists(root + "/R"))
    file.Fail(root, "has only one of the constraint matrices V and R (both or neither)");
  if (file.Exists(root + "/V")) {
    local.V = file.ReadMatrix(root + "/V");
    local.R = file.ReadMatrix(root + "/R");
    const int p = local.R->rows;
    if (local.R->cols != p)
      file.Fail(root + "/R", "is " + Shape(*local.R) + ", expected square");
    if (local.V->rows != m || local.V->cols != p)
      file.Fail(root + "/V", "is " + Shape(*local.V) + ", expected " + Str(m) + " x " +
                                 Str(p) + " (rows of W x rows of R)");
  }
  const std::string vectors = root + "/vectors";
  file.RequireGroup(vectors);
  local.q = file.ReadDoubles(vectors + "/q", m);
  local.mu = ReadMu(file, vectors + "/mu", m / local.spacedim);
  if (local.R) local.s = file.ReadDoubles(vectors + "/s", local.R->rows);
  local.info = ReadInfo(file, root);
  return local;
}

FclibGlobal ReadGlobal(const FclibFile& file) {
  const std::string root = "/fclib_global";
  file.RequireGroup(root);
  FclibGlobal global;
  global.spacedim = ReadSpacedim(file, root);
  global.M = file.ReadMatrix(root + "/M");
  const int n = global.M.rows;
  if (global.M.cols != n)
    file.Fail(root + "/M", "is " + Shape(global.M) + ", expected square");
  global.H = file.ReadMatrix(root + "/H");
  const int m = global.H.cols;
  if (global.H.rows != n || m % global.spacedim != 0)
    file.Fail(root + "/H", "is " + Shape(global.H) + ", expected " + Str(n) +
                               " rows (as M) and a column count that is a multiple of " +
                               "spacedim = " + Str(global.spacedim));
  if (file.Exists(root + "/G")) {
    global.G = file.ReadMatrix(root + "/G");
    if (global.G->rows != n)
      file.Fail(root + "/G",
                "is " + Shape(*global.G) + ", expected " + Str(n) + " rows (as M)");
  }
  const std::string vectors = root + "/vectors";
  file.RequireGroup(vectors);
  global.f = file.ReadDoubles(vectors + "/f", n);
  global.w = file.ReadDoubles(vectors + "/w", m);
  global.mu = ReadMu(file, vectors + "/mu", m / global.spacedim);
  if (global.G) global.b = file.ReadDoubles(vectors + "/b", global.G->cols);
  global.info = ReadInfo(file, root);
  return global;
}

}  // namespace

SparseMatrix FclibMatrix::ToSparse() const {
  std::vector<Eigen::Triplet<double>> entries;
  if (nz >= 0) {
    entries.reserve(nz);
    for (int k = 0; k < nz; ++k) entries.emplace_back(i[k], p[k], x[k]);
  } else {
    const bool by_columns = nz == -1;
    const int outer = by_columns ? cols : rows;
    entries.reserve(p[outer]);
    for (int o = 0; o < outer; ++o)
      for (int k = p[o]; k < p[o + 1]; ++k)
        entries.emplace_back(by_columns ? i[k] : o, by_columns ? o : i[k], x[k]);
  }
  SparseMatrix a(rows, cols);
  a.setFromTriplets(entries.begin(), entries.end());
  return a;
}

FclibKind ReadFclibKind(const std::string& path) { return Kind(FclibFile(path)); }

FclibLocal ReadFclibLocalGroup(const std::string& path) {
  return ReadLocal(FclibFile(path));
}

FclibGlobal ReadFclibGlobalGroup(const std::string& path) {
  return ReadGlobal(FclibFile(path));
}

std::optional<FclibSolution> ReadFclibSolutionGroup(const std::string& path) {
  const FclibFile file(path);
  if (!file.Exists("/solution")) return std::nullopt;
  file.RequireGroup("/solution");
  int nv = 0, nr = 0, nl = 0;  // sizes of v, u and r, lambda from the problem
  switch (Kind(file)) {
    case FclibKind::kLocal: {
      const FclibLocal local = ReadLocal(file);
      nr = local.W.rows;
      nl = local.R ? local.R->rows : 0;
      break;
    }
    case FclibKind::kGlobal: {
      const FclibGlobal global = ReadGlobal(file);
      nv = global.M.rows;
      nr = global.H.cols;
      nl = global.G ? global.G->cols : 0;
      break;
    }
    default:
      file.Fail("/solution",
                "present without an FCLIB local or global problem to size it");
  }
  FclibSolution solution;
  if (nv > 0) solution.v = file.ReadDoubles("/solution/v", nv);
  if (nl > 0) solution.l = file.ReadDoubles("/solution/l", nl);
  solution.u = file.ReadDoubles("/solution/u", nr);
  solution.r = file.ReadDoubles("/solution/r", nr);
  return solution;
}

}  // namespace ncp::fc::internal
