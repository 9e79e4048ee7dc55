#include "memloop/run_csv.h"

#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "memloop/errors.h"

namespace memloop {
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

RunCsvWriter::RunCsvWriter(const std::string& path) : path_(path), out_(path) {
  if (!out_) throw InputError(path, "cannot write the results file");
  out_ << "image,name,location_id,matched_image,matched_location,matched_images,hypothesis_id,"
          "hypothesis_value,hypothesis_images,virtual_place,rehearsal_merged,features,words,"
          "iteration_ms,"
          "signature_ms,rehearsal_ms,likelihood_ms,filter_ms,selection_ms,retrieval_ms,"
          "transfer_ms,stm_size,wm_size,ltm_size,dictionary_size,retrieved,transferred\n";
}

void RunCsvWriter::Write(const std::string& image_name, const Result& result) {
  const StageTimes& t = result.times;
  out_ << result.image_index << ',' << Quoted(image_name) << ',' << result.location_id << ',';
  if (result.HasLoopClosure()) {
    out_ << result.loop_closure_images.front() << ',' << result.loop_closure_id << ','
         << Join(result.loop_closure_images);
  } else {
    out_ << ",,";
  }
  out_ << ',' << result.hypothesis_id << ',' << result.hypothesis_value << ','
       << Join(result.hypothesis_images) << ',' << result.virtual_place_probability << ','
       << result.rehearsal_merged_id << ',' << result.feature_count << ',' << result.word_count
       << ',' << t.total_ms << ',' << t.signature_ms << ',' << t.rehearsal_ms << ','
       << t.likelihood_ms << ',' << t.filter_ms << ',' << t.selection_ms << ',' << t.retrieval_ms
       << ',' << t.transfer_ms << ',' << result.stm_size << ',' << result.wm_size << ','
       << result.ltm_size << ',' << result.dictionary_size << ',' << Join(result.retrieved_ids)
       << ',' << Join(result.transferred_ids) << '\n';
  if (!out_) throw InputError(path_, "writing the results failed");
}

namespace {

// Splits one CSV line; fields may be quoted ("a,b" and "" for a quote inside).
std::vector<std::string> SplitCsvLine(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
      fields.back() += '"';
      ++i;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      fields.emplace_back();
    } else if (c != '\r') {
      fields.back() += c;
    }
  }
  return fields;
}

}  // namespace

std::vector<RunRow> ReadRunCsv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot be read");
  std::string line;
  if (!std::getline(in, line)) throw InputError(path, "is empty: not a memloop run CSV");
  std::map<std::string, size_t> column;
  const std::vector<std::string> header = SplitCsvLine(line);
  for (size_t i = 0; i < header.size(); ++i) column[header[i]] = i;
  for (const char* required :
       {"image", "name", "location_id", "matched_images", "hypothesis_id", "hypothesis_value",
        "hypothesis_images", "iteration_ms", "wm_size", "dictionary_size"}) {
    if (!column.count(required)) {
      throw InputError(path, std::string("not a memloop run CSV (no column '") + required + "')");
    }
  }
  std::vector<RunRow> rows;
  for (int number = 2; std::getline(in, line); ++number) {
    if (line.empty() || line == "\r") continue;
    const std::vector<std::string> fields = SplitCsvLine(line);
    if (fields.size() != header.size()) {
      throw InputError(path, "line " + std::to_string(number) + " has " +
                                 std::to_string(fields.size()) + " fields, the header " +
                                 std::to_string(header.size()));
    }
    const auto text = [&](const char* name) { return fields[column.at(name)]; };
    const auto number_of = [&](const char* name) {
      const std::string& field = text(name);
      char* end = nullptr;
      const double value = std::strtod(field.c_str(), &end);
      if (field.empty() || end != field.c_str() + field.size()) {
        throw InputError(path, "line " + std::to_string(number) + ": " + name + " '" + field +
                                   "' is not a number");
      }
      return value;
    };
    const auto list_of = [&](const char* name) {
      std::vector<ImageIndex> values;
      std::stringstream list(text(name));
      for (std::string item; std::getline(list, item, ';');) {
        char* end = nullptr;
        const long value = std::strtol(item.c_str(), &end, 10);
        if (item.empty() || end != item.c_str() + item.size()) {
          throw InputError(path, "line " + std::to_string(number) + ": " + name + " '" +
                                     text(name) + "' is not a list of images");
        }
        values.push_back(static_cast<ImageIndex>(value));
      }
      return values;
    };
    RunRow row;
    row.image = static_cast<ImageIndex>(number_of("image"));
    row.name = text("name");
    row.location_id = static_cast<LocationId>(number_of("location_id"));
    row.matched_images = list_of("matched_images");
    row.hypothesis_id = static_cast<LocationId>(number_of("hypothesis_id"));
    row.hypothesis_value = number_of("hypothesis_value");
    row.hypothesis_images = list_of("hypothesis_images");
    row.iteration_ms = number_of("iteration_ms");
    row.wm_size = static_cast<int>(number_of("wm_size"));
    row.dictionary_size = static_cast<int>(number_of("dictionary_size"));
    rows.push_back(std::move(row));
  }
  if (rows.empty()) throw InputError(path, "holds no image row");
  return rows;
}

}  // namespace memloop
