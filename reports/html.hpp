#pragma once
// A tiny HTML builder for the report: escaped text, tables, figures (embedded PNGs). No
// scripts, CSS inline, no external references.
#include <sstream>
#include <cstdint>
#include <string>
#include <vector>

namespace orthosonar::reports {

std::string html_escape(const std::string& text);

// RFC 4648 base64 (OpenSSL's EVP_EncodeBlock), no line breaks.
std::string base64(const std::vector<uint8_t>& bytes);

class HtmlDoc {
 public:
  explicit HtmlDoc(const std::string& title);
  void heading(const std::string& text, int level = 2);
  void paragraph(const std::string& text, const std::string& css_class = "");
  void table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows);
  // An image embedded as a data URI (the report needs nothing beside it), with a caption;
  // `mime` is image/png or image/jpeg; `file` names the PNG written beside the report
  // (data-file, for readers).
  void figure(const std::vector<uint8_t>& bytes, const std::string& mime, const std::string& file,
              const std::string& caption);
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
