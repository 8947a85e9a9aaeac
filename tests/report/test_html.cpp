// The Markdown subset of the reports rendered to HTML: structure and escaping.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "report/html.h"

namespace gyrosid {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

TEST(Html, RendersTheReportSubset) {
  const std::string md =
      "# Title <x>\n\nA paragraph with `code`, **bold** and a [link](data/a.csv)\nspanning two lines.\n\n"
      "| model | rms |\n|---|---|\n| rbf | 0.1 |\n| classical | 12 |\n\n- one\n- two\n\n![surface](surfaces/a.png)\n";
  const std::string html = markdown_to_html(md, "t & u");
  EXPECT_THAT(html, HasSubstr("<title>t &amp; u</title>"));
  EXPECT_THAT(html, HasSubstr("<h1>Title &lt;x&gt;</h1>"));
  EXPECT_THAT(html, HasSubstr("<p>A paragraph with <code>code</code>, <strong>bold</strong> and a <a href=\"data/a.csv\">link</a> spanning two lines.</p>"));
  EXPECT_THAT(html, HasSubstr("<tr><th>model</th><th>rms</th></tr>\n<tr><td>rbf</td><td>0.1</td></tr>\n<tr><td>classical</td><td>12</td></tr>"));
  EXPECT_THAT(html, HasSubstr("<ul>\n<li>one</li>\n<li>two</li>\n</ul>"));
  EXPECT_THAT(html, HasSubstr("<img src=\"surfaces/a.png\" alt=\"surface\">"));
  EXPECT_THAT(html, Not(HasSubstr("|---|")));
}

}  // namespace
}  // namespace gyrosid
