#include "libbead/io/mat_file.h"

#include <matio.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <set>

#include "libbead/core/error.h"
#include "libbead/io/contained.h"

namespace bead {
namespace {

struct MatCloser {
  void operator()(mat_t* m) const { Mat_Close(m); }
};
struct VarFree {
  void operator()(matvar_t* v) const { Mat_VarFree(v); }
};
using MatPtr = std::unique_ptr<mat_t, MatCloser>;
using VarPtr = std::unique_ptr<matvar_t, VarFree>;

const char* ClassName(matio_classes c) {
  switch (c) {
    case MAT_C_CELL:
      return "a cell array";
    case MAT_C_STRUCT:
      return "a struct";
    case MAT_C_OBJECT:
      return "a MATLAB object";
    case MAT_C_CHAR:
      return "text";
    case MAT_C_SPARSE:
      return "a sparse matrix";
    case MAT_C_FUNCTION:
      return "a function handle";
    case MAT_C_OPAQUE:
      return "a MATLAB object (opaque)";
    case MAT_C_EMPTY:
      return "empty";
    default:
      return "not numeric";
  }
}

bool Numeric(matio_classes c) {
  switch (c) {
    case MAT_C_DOUBLE:
    case MAT_C_SINGLE:
    case MAT_C_INT8:
    case MAT_C_UINT8:
    case MAT_C_INT16:
    case MAT_C_UINT16:
    case MAT_C_INT32:
    case MAT_C_UINT32:
    case MAT_C_INT64:
    case MAT_C_UINT64:
      return true;
    default:
      return false;
  }
}

template <class T>
void Convert(const void* data, std::size_t n, std::vector<double>& out) {
  const T* p = static_cast<const T*>(data);
  out.assign(p, p + n);
}

// The values of a numeric variable as doubles; false when its data did not come.
bool Values(const matvar_t* v, std::size_t n, std::vector<double>& out) {
  if (v->data == nullptr || (v->data_size > 0 && v->nbytes / v->data_size < n)) return false;
  switch (v->class_type) {
    case MAT_C_DOUBLE:
      Convert<double>(v->data, n, out);
      return true;
    case MAT_C_SINGLE:
      Convert<float>(v->data, n, out);
      return true;
    case MAT_C_INT8:
      Convert<int8_t>(v->data, n, out);
      return true;
    case MAT_C_UINT8:
      Convert<uint8_t>(v->data, n, out);
      return true;
    case MAT_C_INT16:
      Convert<int16_t>(v->data, n, out);
      return true;
    case MAT_C_UINT16:
      Convert<uint16_t>(v->data, n, out);
      return true;
    case MAT_C_INT32:
      Convert<int32_t>(v->data, n, out);
      return true;
    case MAT_C_UINT32:
      Convert<uint32_t>(v->data, n, out);
      return true;
    case MAT_C_INT64:
      Convert<int64_t>(v->data, n, out);
      return true;
    case MAT_C_UINT64:
      Convert<uint64_t>(v->data, n, out);
      return true;
    default:
      return false;
  }
}

// Whether a variable of `values` elements of `klass` could be in a file of
// `file_bytes`: deflate packs at most about 1032:1 (zlib's technical
// notes), so a header declaring more is corrupt. libmatio would allocate
// whatever a corrupt header says (gigabytes) before finding out.
bool Fits(std::size_t values, matio_classes klass, std::uintmax_t file_bytes) {
  const std::size_t element = std::max<std::size_t>(1, Mat_SizeOfClass(klass));
  return values <= (file_bytes * 1100 + 4096) / element;
}

// The declared element count, saturating (a corrupt header may declare
// dimensions whose product overflows).
std::size_t Elements(const matvar_t* v) {
  std::size_t n = 1;
  for (int i = 0; i < v->rank; ++i) {
    if (v->dims[i] != 0 && n > SIZE_MAX / v->dims[i]) return SIZE_MAX;
    n *= v->dims[i];
  }
  return n;
}

}  // namespace

const MatVector* MatContents::Find(const std::string& name) const {
  for (const MatVector& v : vectors)
    if (v.name == name) return &v;
  return nullptr;
}

std::string MatContents::Names() const {
  std::string all;
  for (const MatVector& v : vectors) all += (all.empty() ? "" : ", ") + v.name;
  return all.empty() ? "none" : all;
}

// Both readers walk the file once: Mat_VarRead(name) would walk it again
// from its start for every variable, parsing each cell array's every cell
// on the way (a 14000-cell array costs libmatio 4 s a walk, so a WAAM
// acquisition file with 15 vectors took 40 s). A variable's data is read
// where its header stands (Mat_VarReadDataAll), after the header's checks.

namespace {

MatMatrix ReadMatMatrixDirect(const std::string& path, const std::string& name) {
  MatPtr mat(Mat_Open(path.c_str(), MAT_ACC_RDONLY));
  if (!mat) throw Error(Located(path, "", "not a MATLAB .mat file libmatio can open (v4, v5 or v7.3)"));
  const std::uintmax_t file_bytes = std::filesystem::file_size(path);
  std::string numeric, why;  // why: what makes the variable unusable, from its header
  bool found = false;
  for (;;) {
    VarPtr v(Mat_VarReadNextInfo(mat.get()));
    if (!v) break;
    if (v->name == nullptr) continue;
    if (name == v->name && !found) {
      found = true;
      if (!Numeric(v->class_type))
        why = std::string("is ") + ClassName(v->class_type);
      else if (v->isComplex)
        why = "is complex";
      else if (v->rank != 2)
        why = "has " + std::to_string(v->rank) + " dimensions, not 2";
      else if (!Fits(Elements(v.get()), v->class_type, file_bytes))
        why = "declares " + std::to_string(Elements(v.get())) + " values, more than the file could hold (corrupt)";
      if (why.empty()) {  // the rest of the file is read only to name what else is there, on an error
        if (Mat_VarReadDataAll(mat.get(), v.get()) != 0) throw Error(Located(path, name, "its data could not be read"));
        MatMatrix m{name, v->dims[0], v->dims[1], {}};
        if (m.rows * m.cols == 0) throw Error(Located(path, name, "is empty"));
        if (!Values(v.get(), m.rows * m.cols, m.values)) throw Error(Located(path, name, "its data could not be read"));
        return m;
      }
    }
    if (Numeric(v->class_type) && !v->isComplex && v->rank <= 2)
      numeric += (numeric.empty() ? "" : ", ") + std::string(v->name);
  }
  const std::string there = " (its numeric variables: " + (numeric.empty() ? std::string("none") : numeric) + ")";
  if (!found) throw Error(Located(path, name, "no such variable" + there));
  throw Error(Located(path, name, why + there));
}

MatContents ReadMatVectorsDirect(const std::string& path) {
  MatPtr mat(Mat_Open(path.c_str(), MAT_ACC_RDONLY));
  if (!mat) throw Error(Located(path, "", "not a MATLAB .mat file libmatio can open (v4, v5 or v7.3)"));
  const std::uintmax_t file_bytes = std::filesystem::file_size(path);
  MatContents out;
  std::set<std::string> seen;
  int unnamed = 0;
  for (;;) {
    VarPtr v(Mat_VarReadNextInfo(mat.get()));
    if (!v) break;
    const std::string name = v->name ? v->name : "";
    if (name.empty()) {
      ++unnamed;
      continue;
    }
    if (!seen.insert(name).second) {  // MATLAB's load keeps the first
      out.skipped.push_back(name + ": written twice; the first is used");
      continue;
    }
    if (!Numeric(v->class_type)) {
      out.skipped.push_back(name + ": " + ClassName(v->class_type));
      continue;
    }
    if (v->isComplex) {
      out.skipped.push_back(name + ": complex");
      continue;
    }
    const std::size_t n = Elements(v.get());
    std::size_t longest = 0;
    for (int i = 0; i < v->rank; ++i) longest = std::max<std::size_t>(longest, v->dims[i]);
    if (!Fits(n, v->class_type, file_bytes)) {
      out.skipped.push_back(name + ": declares " + std::to_string(n) + " values, more than the file could hold");
      continue;
    }
    if (v->rank > 2 || n != longest || n == 0) {
      out.skipped.push_back(name + ": a matrix, not a vector (" + std::to_string(v->rank) + " dimensions, " +
                            std::to_string(n) + " values)");
      continue;
    }
    MatVector mv{name, {}};
    if (Mat_VarReadDataAll(mat.get(), v.get()) != 0 || !Values(v.get(), n, mv.values)) {
      out.skipped.push_back(name + ": its data could not be read");
      continue;
    }
    out.vectors.push_back(std::move(mv));
  }
  if (unnamed > 0) out.skipped.push_back(std::to_string(unnamed) + " unnamed: MATLAB's objects and function workspace");
  return out;
}

// Bytes for the trip from the contained child (io/contained.h): sizes as
// 8-byte counts, strings and doubles as they lie in memory (one machine).
void PutSize(std::string& out, std::size_t n) { out.append(reinterpret_cast<const char*>(&n), sizeof n); }
void PutString(std::string& out, const std::string& s) {
  PutSize(out, s.size());
  out += s;
}
void PutDoubles(std::string& out, const std::vector<double>& v) {
  PutSize(out, v.size());
  out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(double));
}
struct Reader {
  const std::string& in;
  std::size_t at = 0;
  std::size_t Size() {
    std::size_t n = 0;
    in.copy(reinterpret_cast<char*>(&n), sizeof n, at);
    at += sizeof n;
    return n;
  }
  std::string String() {
    const std::size_t n = Size();
    std::string s = in.substr(at, n);
    at += n;
    return s;
  }
  std::vector<double> Doubles() {
    std::vector<double> v(Size());
    in.copy(reinterpret_cast<char*>(v.data()), v.size() * sizeof(double), at);
    at += v.size() * sizeof(double);
    return v;
  }
};

}  // namespace

// libmatio sizes what it allocates from a file's headers before it reads
// anything: the file is read in a contained child (io/contained.h) and
// only its result comes back; libmatio never runs in the caller.
MatMatrix ReadMatMatrix(const std::string& path, const std::string& name) {
  const std::string bytes = RunContained(
      path, "matio",
      [&] {
        const MatMatrix m = ReadMatMatrixDirect(path, name);
        std::string out;
        PutString(out, m.name);
        PutSize(out, m.rows);
        PutSize(out, m.cols);
        PutDoubles(out, m.values);
        return out;
      },
      LimitsForWholeFile(path));
  Reader r{bytes};
  MatMatrix m;
  m.name = r.String();
  m.rows = r.Size();
  m.cols = r.Size();
  m.values = r.Doubles();
  return m;
}

MatContents ReadMatVectors(const std::string& path) {
  const std::string bytes = RunContained(
      path, "matio",
      [&] {
        const MatContents c = ReadMatVectorsDirect(path);
        std::string out;
        PutSize(out, c.vectors.size());
        for (const MatVector& v : c.vectors) PutString(out, v.name), PutDoubles(out, v.values);
        PutSize(out, c.skipped.size());
        for (const std::string& s : c.skipped) PutString(out, s);
        return out;
      },
      LimitsForWholeFile(path));
  Reader r{bytes};
  MatContents c;
  c.vectors.resize(r.Size());
  for (MatVector& v : c.vectors) v.name = r.String(), v.values = r.Doubles();
  c.skipped.resize(r.Size());
  for (std::string& s : c.skipped) s = r.String();
  return c;
}

}  // namespace bead
