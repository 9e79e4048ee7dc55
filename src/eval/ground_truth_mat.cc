#include "eval/ground_truth_mat.h"

#include <matio.h>
#include <sys/stat.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <memory>
#include <vector>

#include "memloop/errors.h"
#include "memloop/ground_truth.h"

namespace memloop {
namespace {

// The byte sizes of the top-level elements (variables) of a MATLAB v5 file, in file order.
// libmatio reads a truncated variable as zeros without an error, so the lengths written in the
// element tags are checked against the file's size first. Empty for v4 and v7.3 (HDF5) files.
std::vector<uint64_t> V5ElementSizes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char header[128];
  if (!in.read(header, sizeof(header))) return {};
  // The endian indicator is 'M' << 8 | 'I' in the writer's byte order.
  uint16_t indicator = 0;
  std::memcpy(&indicator, header + 126, 2);
  const bool native = indicator == ('M' << 8 | 'I');
  const bool swapped = indicator == ('I' << 8 | 'M');
  uint16_t version = 0;
  std::memcpy(&version, header + 124, 2);
  if (swapped) version = static_cast<uint16_t>((version >> 8) | (version << 8));
  if (!(swapped || native) || version != 0x0100) return {};
  in.seekg(0, std::ios::end);
  const uint64_t file_size = static_cast<uint64_t>(in.tellg());
  std::vector<uint64_t> sizes;
  for (uint64_t position = 128; position < file_size;) {
    uint32_t tag[2];
    in.seekg(static_cast<std::streamoff>(position));
    if (!in.read(reinterpret_cast<char*>(tag), sizeof(tag))) {
      throw InputError(path,
                       "the .mat file is truncated: it ends inside a variable's header, at "
                       "byte " +
                           std::to_string(file_size));
    }
    uint32_t bytes = tag[1];
    if (swapped) bytes = __builtin_bswap32(bytes);
    constexpr uint32_t kCompressed = 15;  // miCOMPRESSED: not padded to 8 bytes
    const uint32_t type = swapped ? __builtin_bswap32(tag[0]) : tag[0];
    const uint64_t end = position + 8 + bytes;
    if (end > file_size) {
      throw InputError(path, "the .mat file is truncated: variable " +
                                 std::to_string(sizes.size() + 1) + " needs " +
                                 std::to_string(bytes) + " bytes, the file ends " +
                                 std::to_string(end - file_size) + " bytes short");
    }
    sizes.push_back(bytes);
    position = type == kCompressed ? end : (end + 7) / 8 * 8;
  }
  return sizes;
}

struct MatFile {
  explicit MatFile(const std::string& path) : handle(Mat_Open(path.c_str(), MAT_ACC_RDONLY)) {
    if (handle == nullptr) throw InputError(path, "cannot be read as a MATLAB .mat file");
  }
  ~MatFile() { Mat_Close(handle); }
  mat_t* handle;
};

struct VariableFree {
  void operator()(matvar_t* variable) const { Mat_VarFree(variable); }
};
using Variable = std::unique_ptr<matvar_t, VariableFree>;

bool IsNumericMatrix(const matvar_t& variable) {
  return variable.class_type >= MAT_C_DOUBLE && variable.class_type <= MAT_C_UINT64 &&
         variable.rank == 2 && !variable.isComplex;
}

// The variable's values as doubles; MATLAB stores columns first.
cv::Mat Values(const matvar_t& variable) {
  const int rows = static_cast<int>(variable.dims[0]);
  const int cols = static_cast<int>(variable.dims[1]);
  cv::Mat values(rows, cols, CV_64F);
  const auto read = [&](const auto* data) {
    for (int c = 0; c < cols; ++c) {
      for (int r = 0; r < rows; ++r) {
        values.at<double>(r, c) = static_cast<double>(data[static_cast<size_t>(c) * rows + r]);
      }
    }
  };
  switch (variable.data_type) {
    case MAT_T_DOUBLE:
      read(static_cast<const double*>(variable.data));
      break;
    case MAT_T_SINGLE:
      read(static_cast<const float*>(variable.data));
      break;
    case MAT_T_UINT8:
      read(static_cast<const unsigned char*>(variable.data));
      break;
    case MAT_T_INT8:
      read(static_cast<const signed char*>(variable.data));
      break;
    case MAT_T_INT16:
      read(static_cast<const short*>(variable.data));
      break;
    case MAT_T_UINT16:
      read(static_cast<const unsigned short*>(variable.data));
      break;
    case MAT_T_INT32:
      read(static_cast<const int*>(variable.data));
      break;
    case MAT_T_UINT32:
      read(static_cast<const unsigned int*>(variable.data));
      break;
    default:
      return cv::Mat();
  }
  return values;
}

}  // namespace

cv::Mat LoadMatFile(const std::string& path, int image_count) {
  const std::vector<uint64_t> element_sizes = V5ElementSizes(path);
  // First pass, headers only: which variable, and whether its size is the run's, before any
  // data is read (a 240-byte file may declare a matrix of gigabytes).
  std::string name;
  std::string skipped;
  {
    MatFile file(path);
    for (size_t index = 0; name.empty(); ++index) {
      Variable variable(Mat_VarReadNextInfo(file.handle));
      if (!variable) break;
      const std::string variable_name = variable->name ? variable->name : "?";
      if (!IsNumericMatrix(*variable)) {
        skipped += (skipped.empty() ? "" : ", ") + variable_name;
        continue;
      }
      const size_t rows = variable->dims[0];
      const size_t cols = variable->dims[1];
      if (rows != cols) {
        throw InputError(path, "variable '" + variable_name + "' is " + std::to_string(rows) + "x" +
                                   std::to_string(cols) + ", not square");
      }
      if (rows != static_cast<size_t>(image_count)) {
        throw InputError(path, "the ground truth is " + std::to_string(rows) + "x" +
                                   std::to_string(cols) + " but the run has " +
                                   std::to_string(image_count) + " images");
      }
      // The stored type is known only once the data is read (MATLAB may store doubles as
      // integers), so one byte per value is the floor.
      if (index < element_sizes.size() && variable->compression == MAT_COMPRESSION_NONE &&
          element_sizes[index] < rows * cols) {
        throw InputError(path, "variable '" + variable_name + "' declares " + std::to_string(rows) +
                                   "x" + std::to_string(cols) + " values but holds " +
                                   std::to_string(element_sizes[index]) +
                                   " bytes: the matrix is truncated");
      }
      name = variable_name;
    }
  }
  if (name.empty()) {
    throw InputError(path, "no square numeric matrix in the .mat file" +
                               (skipped.empty() ? std::string() : " (variables: " + skipped + ")"));
  }
  MatFile file(path);
  Variable variable(Mat_VarRead(file.handle, name.c_str()));
  const cv::Mat values = variable && variable->data ? Values(*variable) : cv::Mat();
  if (values.empty()) {
    throw InputError(path, "variable '" + name +
                               "' cannot be read (damaged, or of a type other "
                               "than double, single or an integer of 8-32 bits)");
  }
  cv::Mat labels(values.rows, values.cols, CV_8U, cv::Scalar(GroundTruth::kIgnored));
  labels.setTo(GroundTruth::kLoop, values == 1);
  labels.setTo(GroundTruth::kNone, values == 0);
  return labels;
}

}  // namespace memloop
