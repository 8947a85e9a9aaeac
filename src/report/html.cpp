#include "report/html.h"

#include <sstream>
#include <vector>

namespace gyrosid {

std::string html_escape(std::string_view text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

namespace {

// Inline markup: ![alt](src), [text](href), `code`, **bold**; everything else escaped.
std::string inline_html(std::string_view s) {
  std::string out;
  std::size_t i = 0;
  while (i < s.size()) {
    const bool image = s.compare(i, 2, "![") == 0;
    if (image || s[i] == '[') {
      const std::size_t open = i + (image ? 2 : 1), close = s.find("](", open);
      const std::size_t end = close == std::string_view::npos ? close : s.find(')', close + 2);
      if (end != std::string_view::npos) {
        const std::string text = html_escape(s.substr(open, close - open));
        const std::string target = html_escape(s.substr(close + 2, end - close - 2));
        out += image ? "<img src=\"" + target + "\" alt=\"" + text + "\">" : "<a href=\"" + target + "\">" + text + "</a>";
        i = end + 1;
        continue;
      }
    }
    if (s[i] == '`') {
      const std::size_t end = s.find('`', i + 1);
      if (end != std::string_view::npos) {
        out += "<code>" + html_escape(s.substr(i + 1, end - i - 1)) + "</code>";
        i = end + 1;
        continue;
      }
    }
    if (s.compare(i, 2, "**") == 0) {
      const std::size_t end = s.find("**", i + 2);
      if (end != std::string_view::npos) {
        out += "<strong>" + inline_html(s.substr(i + 2, end - i - 2)) + "</strong>";
        i = end + 2;
        continue;
      }
    }
    out += html_escape(s.substr(i, 1));
    ++i;
  }
  return out;
}

std::vector<std::string_view> table_cells(std::string_view line) {
  std::vector<std::string_view> cells;
  if (!line.empty() && line.front() == '|') line.remove_prefix(1);
  if (!line.empty() && line.back() == '|') line.remove_suffix(1);
  std::size_t start = 0;
  while (true) {
    const std::size_t bar = line.find('|', start);
    std::string_view cell = line.substr(start, bar == std::string_view::npos ? std::string_view::npos : bar - start);
    while (!cell.empty() && cell.front() == ' ') cell.remove_prefix(1);
    while (!cell.empty() && cell.back() == ' ') cell.remove_suffix(1);
    cells.push_back(cell);
    if (bar == std::string_view::npos) break;
    start = bar + 1;
  }
  return cells;
}

bool is_rule(std::string_view line) { return line.find("---") != std::string_view::npos && line.find_first_not_of("|-: ") == std::string_view::npos; }

}  // namespace

std::string markdown_to_html(std::string_view md, const std::string& title) {
  std::ostringstream out;
  out << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" << html_escape(title) << "</title>\n"
      << "<style>body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;line-height:1.45}"
         "table{border-collapse:collapse;margin:1em 0}th,td{border:1px solid #bbb;padding:.25em .6em;text-align:right}"
         "th:first-child,td:first-child{text-align:left}img{max-width:100%}code{background:#f3f3f3;padding:0 .2em}</style>\n"
      << "</head>\n<body>\n";
  std::vector<std::string_view> lines;
  for (std::size_t pos = 0; pos <= md.size();) {
    const std::size_t eol = md.find('\n', pos);
    lines.push_back(md.substr(pos, eol == std::string_view::npos ? std::string_view::npos : eol - pos));
    if (eol == std::string_view::npos) break;
    pos = eol + 1;
  }
  std::string paragraph;
  auto flush = [&] {
    if (!paragraph.empty()) out << "<p>" << inline_html(paragraph) << "</p>\n";
    paragraph.clear();
  };
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string_view line = lines[i];
    if (line.empty()) {
      flush();
    } else if (line.front() == '#') {
      flush();
      const std::size_t level = std::min<std::size_t>(line.find_first_not_of('#'), 6);
      out << "<h" << level << ">" << inline_html(line.substr(std::min(line.size(), level + 1))) << "</h" << level << ">\n";
    } else if (line.front() == '|' && i + 1 < lines.size() && is_rule(lines[i + 1])) {
      flush();
      out << "<table>\n<tr>";
      for (auto c : table_cells(line)) out << "<th>" << inline_html(c) << "</th>";
      out << "</tr>\n";
      for (i += 2; i < lines.size() && !lines[i].empty() && lines[i].front() == '|'; ++i) {
        out << "<tr>";
        for (auto c : table_cells(lines[i])) out << "<td>" << inline_html(c) << "</td>";
        out << "</tr>\n";
      }
      --i;
      out << "</table>\n";
    } else if (line.rfind("- ", 0) == 0) {
      flush();
      out << "<ul>\n";
      for (; i < lines.size() && lines[i].rfind("- ", 0) == 0; ++i) out << "<li>" << inline_html(lines[i].substr(2)) << "</li>\n";
      --i;
      out << "</ul>\n";
    } else {
      if (!paragraph.empty()) paragraph += ' ';
      paragraph.append(line);
    }
  }
  flush();
  out << "<script>\n"
         "window.addEventListener('load', function () {\n"
         "  var images = document.images, loaded = 0;\n"
         "  for (var i = 0; i < images.length; ++i) if (images[i].complete && images[i].naturalWidth > 0) ++loaded;\n"
         "  document.body.setAttribute('data-images', images.length);\n"
         "  document.body.setAttribute('data-images-loaded', loaded);\n"
         "});\n</script>\n</body>\n</html>\n";
  return out.str();
}

}  // namespace gyrosid
