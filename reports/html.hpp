#pragma once
// A tiny HTML builder for the report: escaped text, tables, figures. No scripts, CSS inline.
#include <sstream>
#include <string>
#include <vector>

namespace orthosonar::reports {

std::string html_escape(const std::string& text);

class HtmlDoc {
 public:
  explicit HtmlDoc(const std::string& title);
  void heading(const std::string& text, int level = 2);
  void paragraph(const std::string& text, const std::string& css_class = "");
  void table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows);
  // An image by relative path with a caption; wide figures span the page.
  void figure(const std::string& relative_path, const std::string& caption);
  void begin_gallery();
  void end_gallery();
  void list(const std::vector<std::string>& items);
  // A collapsed section (<details>) for long tables such as the configuration.
  void begin_details(const std::string& summary);
  void end_details();
  std::string finish();

 private:
  std::ostringstream body_;
  std::string title_;
};

}  // namespace orthosonar::reports
