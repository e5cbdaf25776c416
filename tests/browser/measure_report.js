(function () {
  var out = {width: window.innerWidth, overflow: [], text_out: [], truncated: [], empty: [],
             channels: [], dists: [], summary_tables: [], headings: [], plot_texts: [], error: "",
             token_breaks: [], cells: 0, verdict_cells: 0, probe_caught: false};
  function name(e) {
    var s = e.tagName.toLowerCase();
    if (e.id) s += "#" + e.id;
    if (e.className && typeof e.className === "string") s += "." + e.className.split(" ").join(".");
    var sec = e.closest("section.channel, section#lot");
    return s + (sec && sec.id ? " in #" + sec.id : "");
  }
  function shown(e) { return e.getClientRects().length > 0; }
  // The tokens of a table cell (runs of non-blank characters within one text node: a number, a
  // unit, a name) that the browser laid out over more than one line: a range over each token
  // has boxes at different heights when the line breaks inside it.
  function brokenTokens(cell) {
    var broken = [], walker = document.createTreeWalker(cell, NodeFilter.SHOW_TEXT), node;
    while ((node = walker.nextNode())) {
      var text = node.textContent, re = /\S+/g, m;
      while ((m = re.exec(text))) {
        var range = document.createRange();
        range.setStart(node, m.index);
        range.setEnd(node, m.index + m[0].length);
        var tops = {};
        Array.prototype.forEach.call(range.getClientRects(), function (r) {
          if (r.width > 0) tops[Math.round(r.top)] = true;
        });
        if (Object.keys(tops).length > 1) broken.push(m[0]);
      }
    }
    return broken;
  }
  function unitOf(label) { var m = /\(([^()]*)\)\s*$/.exec(label || ""); return m ? m[1] : null; }
  try {
    var details = Array.prototype.slice.call(document.querySelectorAll("details"));
    var closed = details.map(function (d) { return !d.open; });
    details.forEach(function (d) { d.open = true; });
    // 1. Nothing wider than its box: a scrolled, clipped or overflowing element.
    document.querySelectorAll("body, body *").forEach(function (e) {
      if (e instanceof SVGElement && !(e instanceof SVGSVGElement)) return;
      if (e.clientWidth > 0 && e.scrollWidth > e.clientWidth + 1)
        out.overflow.push(name(e) + ": scrollWidth " + e.scrollWidth + " > clientWidth " + e.clientWidth);
    });
    if (document.documentElement.scrollWidth > window.innerWidth)
      out.overflow.push("page: " + document.documentElement.scrollWidth + " px wide in a " +
                        window.innerWidth + " px window");
    // 1b. No table cell breaks inside a token, but the free-text cells of a diagnosis (td.wrap,
    // JSON that must break somewhere). First a probe that must be caught: a name in a cell too
    // narrow for it, allowed to break anywhere.
    var probe = document.createElement("table");
    probe.innerHTML = '<tr><td style="white-space:normal;overflow-wrap:anywhere;width:20px;' +
                      'max-width:20px">unit_0001234567</td></tr>';
    document.body.appendChild(probe);
    out.probe_caught = brokenTokens(probe.querySelector("td")).length > 0;
    document.body.removeChild(probe);
    document.querySelectorAll("table td, table th").forEach(function (c) {
      if (!shown(c) || c.classList.contains("wrap")) return;
      out.cells++;
      if (c.classList.contains("verdict") && c.textContent.trim()) out.verdict_cells++;
      brokenTokens(c).forEach(function (t) {
        var table = c.closest("table"), h = table.closest("div") && table.closest("div").querySelector("h3");
        out.token_breaks.push("'" + t + "' in " + name(c) + (h ? " under '" + h.textContent + "'" : ""));
      });
    });
    // 2. Every text of every plot inside its plot; no legend entry cut.
    document.querySelectorAll("svg.plot").forEach(function (svg) {
      var box = svg.getBoundingClientRect();
      svg.querySelectorAll("text").forEach(function (t) {
        if (!shown(t)) return;
        var r = t.getBoundingClientRect();
        if (r.width === 0) return;
        if (r.left < box.left - 1 || r.right > box.right + 1 || r.top < box.top - 1 || r.bottom > box.bottom + 1)
          out.text_out.push(svg.id + ": '" + t.textContent + "' outside the plot");
        out.plot_texts.push(t.textContent);
      });
      svg.querySelectorAll("g.legend text").forEach(function (t) {
        if (t.textContent.indexOf("\u2026") >= 0) out.truncated.push(svg.id + ": '" + t.textContent + "'");
      });
      // 3. A panel with no data drawn: no path or dot in the plot area but reference lines.
      var marks = 0;
      svg.querySelectorAll("g[clip-path] path, g[clip-path] circle, svg > a circle").forEach(function (p) {
        if (!shown(p)) return;
        if (p.tagName === "circle") { marks++; return; }
        var d = p.getAttribute("d") || "", fill = p.getAttribute("fill");
        if (/^M[-\d.]+ [-\d.]+H[-\d.]+$/.test(d)) return;  // a reference line
        if (fill && fill !== "none" && !/^#f4f4f4$/.test(fill)) return;  // a shaded band
        marks++;
      });
      if (marks === 0) out.empty.push(svg.id);
      out.plot_texts.push(svg.getAttribute("aria-label") || "");
    });
    document.querySelectorAll("h1, h2, h3, h4, p, summary, caption").forEach(function (h) {
      out.headings.push(h.textContent);
    });
    // 4. Per channel: the panels, their legends, tick boxes, units and labels.
    document.querySelectorAll("section.channel").forEach(function (sec) {
      var c = {id: sec.id, adev: null, tdev: null, coef_units: {}, detected: [], has_coef: false,
               devtables: null};
      var coef = sec.querySelector("table.coef");
      if (coef) {
        c.has_coef = true;
        // Columns by their headings: "unit" and "detected".
        var heads = Array.prototype.map.call(coef.querySelectorAll("tr:first-child th"),
                                             function (th) { return th.textContent.trim(); });
        var iu = heads.findIndex(function (h) { return /^unit/.test(h); });
        var id = heads.findIndex(function (h) { return /^detected/.test(h); });
        coef.querySelectorAll("tr").forEach(function (tr) {
          var cells = tr.querySelectorAll("td");
          if (cells.length <= Math.max(iu, id) || iu < 0 || id < 0) return;
          var term = cells[0].textContent.trim();
          c.coef_units[term] = cells[iu].firstChild ? cells[iu].firstChild.textContent.trim() : "";
          if (/^yes/.test(cells[id].textContent.trim())) c.detected.push(term);
        });
      }
      ["adev", "tdev"].forEach(function (kind) {
        var svg = sec.querySelector('svg[id$="-' + kind + '"]');
        if (!svg) return;
        var p = {ylabel: "", visible: [], hidden: [], toggles: [], labels_on_curves: []};
        var yl = svg.querySelector('text[transform*="rotate(-90)"]');
        p.ylabel = yl ? yl.textContent : "";
        p.yunit = unitOf(p.ylabel);
        svg.querySelectorAll("g.legend text").forEach(function (t) {
          (shown(t) ? p.visible : p.hidden).push(t.textContent);
        });
        // The tick boxes before the plot: each must show its statistic, hidden until ticked.
        var panel = svg.parentElement;
        panel.querySelectorAll('input[type="checkbox"]').forEach(function (box) {
          var stat = (box.className.match(/t-([A-Za-z0-9_-]+)/) || [])[1] || "";
          var g = svg.querySelectorAll("g.s-" + stat);
          var before = Array.prototype.some.call(g, shown);
          box.click();
          var after = g.length > 0 && Array.prototype.every.call(g, shown);
          box.click();
          p.toggles.push({stat: stat, hidden_before: !before, shown_after: after});
        });
        // Labels in the plot area (slope labels) must not sit on a drawn curve, bar or dot.
        var labels = svg.querySelectorAll("text[paint-order]");
        var paths = Array.prototype.filter.call(svg.querySelectorAll("g[clip-path] path"), function (q) {
          var fill = q.getAttribute("fill");
          return shown(q) && (!fill || fill === "none") &&
                 !/^M[-\d.]+ [-\d.]+H[-\d.]+$/.test(q.getAttribute("d") || "");
        });
        labels.forEach(function (t) {
          if (!shown(t)) return;
          var b = t.getBBox(), hits = 0;
          paths.forEach(function (q) {
            var w = parseFloat(q.getAttribute("stroke-width") || "1") / 2;
            var inside = function (x, y) {
              return x > b.x - w && x < b.x + b.width + w && y > b.y - w && y < b.y + b.height + w;
            };
            var d = q.getAttribute("d") || "", m, re = /M(-?[\d.]+) (-?[\d.]+)h0/g;
            while ((m = re.exec(d))) if (inside(+m[1], +m[2])) hits++;
            var len = q.getTotalLength();
            for (var s = 0; s <= len; s += 1) {
              var pt = q.getPointAtLength(s);
              if (inside(pt.x, pt.y)) { hits++; break; }
            }
          });
          if (hits > 0) p.labels_on_curves.push(t.textContent);
        });
        c[kind] = p;
      });
      var det = sec.querySelector("details");
      if (det) {
        var i = details.indexOf(det);
        c.devtables = {closed: closed[i], tables: det.querySelectorAll("table").length,
                       captions: Array.prototype.map.call(det.querySelectorAll("caption"),
                                                          function (x) { return x.textContent; })};
      }
      out.channels.push(c);
    });
    // 5. The lot: the distribution plots, and units inside each summary table.
    document.querySelectorAll('svg.plot[id^="dist-"]').forEach(function (svg) {
      out.dists.push({id: svg.id, title: svg.getAttribute("aria-label")});
    });
    document.querySelectorAll("table.summary").forEach(function (t) {
      var h = t.closest("div") ? t.closest("div").querySelector("h3") : null;
      out.summary_tables.push(h ? h.textContent : "");
    });
  } catch (e) {
    out.error = String(e && e.stack || e);
  }
  var pre = document.createElement("pre");
  pre.id = "allanlot-measure";
  pre.textContent = JSON.stringify(out);
  document.body.appendChild(pre);
})();
