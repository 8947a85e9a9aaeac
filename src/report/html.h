// HTML beside the Markdown reports: the Markdown subset gyrosid's reports use (headings, paragraphs, lists,
// pipe tables, images, links, inline code, bold) rendered to one self-contained HTML page, so report.md and
// index.html always say the same thing. The page marks itself once its images have loaded
// (<body data-images="N" data-images-loaded="K">), which the browser test reads.
#pragma once

#include <string>
#include <string_view>

namespace gyrosid {

std::string markdown_to_html(std::string_view markdown, const std::string& title);

// Text with &, <, > and " escaped.
std::string html_escape(std::string_view text);

}  // namespace gyrosid
