#include "reports/html.hpp"

#include <algorithm>

#include <openssl/evp.h>

namespace orthosonar::reports {

std::string html_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

HtmlDoc::HtmlDoc(const std::string& title) : title_(title) {}

void HtmlDoc::heading(const std::string& text, int level) {
  body_ << "<h" << level << ">" << html_escape(text) << "</h" << level << ">\n";
}

void HtmlDoc::paragraph(const std::string& text, const std::string& css_class) {
  body_ << "<p" << (css_class.empty() ? "" : " class=\"" + css_class + "\"") << ">" << html_escape(text) << "</p>\n";
}

void HtmlDoc::table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows) {
  body_ << "<table>\n<tr>";
  for (const auto& h : header) body_ << "<th>" << html_escape(h) << "</th>";
  body_ << "</tr>\n";
  for (const auto& row : rows) {
    body_ << "<tr>";
    for (const auto& cell : row) body_ << "<td>" << html_escape(cell) << "</td>";
    body_ << "</tr>\n";
  }
  body_ << "</table>\n";
}

std::string base64(const std::vector<uint8_t>& bytes) {
  std::string out(4 * ((bytes.size() + 2) / 3) + 1, '\0');
  const int n = EVP_EncodeBlock(reinterpret_cast<unsigned char*>(out.data()), bytes.data(), static_cast<int>(bytes.size()));
  out.resize(static_cast<size_t>(std::max(n, 0)));
  return out;
}

void HtmlDoc::figure(const std::vector<uint8_t>& bytes, const std::string& mime, const std::string& file,
                     const std::string& caption) {
  body_ << "<figure><img src=\"data:" << mime << ";base64," << base64(bytes) << "\" alt=\"" << html_escape(caption)
        << "\" data-file=\"" << html_escape(file) << "\"><figcaption>" << html_escape(caption)
        << "</figcaption></figure>\n";
}

void HtmlDoc::begin_gallery() { body_ << "<div class=\"gallery\">\n"; }
void HtmlDoc::end_gallery() { body_ << "</div>\n"; }

void HtmlDoc::list(const std::vector<std::string>& items) {
  body_ << "<ul>\n";
  for (const auto& i : items) body_ << "<li>" << html_escape(i) << "</li>\n";
  body_ << "</ul>\n";
}

void HtmlDoc::begin_details(const std::string& summary) {
  body_ << "<details><summary>" << html_escape(summary) << "</summary>\n";
}
void HtmlDoc::end_details() { body_ << "</details>\n"; }

std::string HtmlDoc::finish() {
  std::ostringstream out;
  out << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" << html_escape(title_)
      << "</title>\n<style>\n"
         "body{font-family:-apple-system,'Segoe UI',Helvetica,Arial,sans-serif;margin:2em auto;max-width:1400px;"
         "padding:0 1.5em;color:#222;background:#fafafa}\n"
         "h1{border-bottom:3px solid #2b4c7e;padding-bottom:.3em}h2{margin-top:1.8em;color:#2b4c7e;"
         "border-bottom:1px solid #ccc}\n"
         "table{border-collapse:collapse;margin:.8em 0;font-size:.92em}th,td{border:1px solid #ccc;"
         "padding:.3em .7em;text-align:left}th{background:#e8edf4}tr:nth-child(even) td{background:#f3f3f3}\n"
         "td{font-family:ui-monospace,Menlo,Consolas,monospace}\n"
         ".gallery{display:flex;flex-wrap:wrap;gap:1em}.gallery figure{flex:1 1 600px;max-width:680px}\n"
         "figure{margin:.5em 0}figure img{width:100%;border:1px solid #bbb;background:#fff}"
         "figcaption{font-size:.9em;color:#555;margin-top:.2em}\n"
         ".note{color:#8a5a00}.meta{color:#555}\n"
         "</style>\n</head>\n<body>\n<h1>"
      << html_escape(title_) << "</h1>\n"
      << body_.str() << "</body>\n</html>\n";
  return out.str();
}

}  // namespace orthosonar::reports
