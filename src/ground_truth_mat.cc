#include "ground_truth_mat.h"

#include <matio.h>

#include "memloop/errors.h"
#include "memloop/ground_truth.h"

namespace memloop {

cv::Mat LoadMatFile(const std::string& path) {
  mat_t* file = Mat_Open(path.c_str(), MAT_ACC_RDONLY);
  if (file == nullptr) throw InputError(path, "cannot be read as a MATLAB .mat file");
  cv::Mat labels;
  std::string skipped;
  while (matvar_t* variable = Mat_VarReadNext(file)) {
    const bool numeric =
        variable->class_type >= MAT_C_DOUBLE && variable->class_type <= MAT_C_UINT64;
    if (labels.empty() && numeric && variable->rank == 2 && !variable->isComplex &&
        variable->data != nullptr) {
      const int rows = static_cast<int>(variable->dims[0]);
      const int cols = static_cast<int>(variable->dims[1]);
      if (rows != cols) {
        const std::string name = variable->name ? variable->name : "?";
        Mat_VarFree(variable);
        Mat_Close(file);
        throw InputError(path, "variable '" + name + "' is " + std::to_string(rows) + "x" +
                                   std::to_string(cols) + ", not square");
      }
      // Read as double whatever the stored class; MATLAB stores columns first.
      cv::Mat values(rows, cols, CV_64F);
      const auto read = [&](auto* data) {
        for (int c = 0; c < cols; ++c) {
          for (int r = 0; r < rows; ++r)
            values.at<double>(r, c) = static_cast<double>(data[c * rows + r]);
        }
      };
      switch (variable->data_type) {
        case MAT_T_DOUBLE:
          read(static_cast<const double*>(variable->data));
          break;
        case MAT_T_SINGLE:
          read(static_cast<const float*>(variable->data));
          break;
        case MAT_T_UINT8:
          read(static_cast<const unsigned char*>(variable->data));
          break;
        case MAT_T_INT8:
          read(static_cast<const signed char*>(variable->data));
          break;
        case MAT_T_INT16:
          read(static_cast<const short*>(variable->data));
          break;
        case MAT_T_UINT16:
          read(static_cast<const unsigned short*>(variable->data));
          break;
        case MAT_T_INT32:
          read(static_cast<const int*>(variable->data));
          break;
        case MAT_T_UINT32:
          read(static_cast<const unsigned int*>(variable->data));
          break;
        default:
          values.release();
      }
      if (!values.empty()) {
        labels = cv::Mat(rows, cols, CV_8U, cv::Scalar(GroundTruth::kIgnored));
        labels.setTo(GroundTruth::kLoop, values == 1);
        labels.setTo(GroundTruth::kNone, values == 0);
      }
    } else if (variable->name) {
      skipped += std::string(skipped.empty() ? "" : ", ") + variable->name;
    }
    Mat_VarFree(variable);
  }
  Mat_Close(file);
  if (labels.empty()) {
    throw InputError(path, "no square numeric matrix in the .mat file" +
                               (skipped.empty() ? std::string() : " (variables: " + skipped + ")"));
  }
  return labels;
}

}  // namespace memloop
