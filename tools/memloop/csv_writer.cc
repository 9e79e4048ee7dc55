#include "csv_writer.h"

#include <sstream>
#include <vector>

#include "memloop/errors.h"

namespace memloop::cli {
namespace {

template <typename T>
std::string Join(const std::vector<T>& values) {
  std::ostringstream text;
  for (size_t i = 0; i < values.size(); ++i) text << (i ? ";" : "") << values[i];
  return text.str();
}

std::string Quoted(const std::string& text) {
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

}  // namespace

CsvWriter::CsvWriter(const std::string& path) : path_(path), out_(path) {
  if (!out_) throw InputError(path, "cannot write the results file");
  out_ << "image,name,location_id,matched_image,matched_location,matched_images,hypothesis_id,"
          "hypothesis_value,virtual_place,rehearsal_merged,features,words,iteration_ms,"
          "signature_ms,rehearsal_ms,likelihood_ms,filter_ms,selection_ms,retrieval_ms,"
          "transfer_ms,stm_size,wm_size,ltm_size,dictionary_size,retrieved,transferred\n";
}

void CsvWriter::Write(const std::string& image_name, const Result& result) {
  const StageTimes& t = result.times;
  out_ << result.image_index << ',' << Quoted(image_name) << ',' << result.location_id << ',';
  if (result.HasLoopClosure()) {
    out_ << result.loop_closure_images.front() << ',' << result.loop_closure_id << ','
         << Join(result.loop_closure_images);
  } else {
    out_ << ",,";
  }
  out_ << ',' << result.hypothesis_id << ',' << result.hypothesis_value << ','
       << result.virtual_place_probability << ',' << result.rehearsal_merged_id << ','
       << result.feature_count << ',' << result.word_count << ',' << t.total_ms << ','
       << t.signature_ms << ',' << t.rehearsal_ms << ',' << t.likelihood_ms << ',' << t.filter_ms
       << ',' << t.selection_ms << ',' << t.retrieval_ms << ',' << t.transfer_ms << ','
       << result.stm_size << ',' << result.wm_size << ',' << result.ltm_size << ','
       << result.dictionary_size << ',' << Join(result.retrieved_ids) << ','
       << Join(result.transferred_ids) << '\n';
  if (!out_) throw InputError(path_, "writing the results failed");
}

}  // namespace memloop::cli
