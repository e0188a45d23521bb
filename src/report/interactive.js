// The interactive views of a seqtopo report (report.html of `seqtopo map` and `seqtopo localize`), on D3 3.5
// (Debian's libjs-d3, inlined before this script). Everything the page shows comes from the JSON data block
// <script type="application/json" id="seqtopo-data"> (include/seqtopo/report/interactive.hpp); nothing is
// fetched. window.seqtopoReport exposes the views for tests and for the curious (state, zoom, select).
(function () {
  "use strict";
  var block = document.getElementById("seqtopo-data");
  if (!block || typeof d3 === "undefined") return;
  var data = JSON.parse(block.textContent);
  var api = (window.seqtopoReport = {data: data});

  // ---- helpers -----------------------------------------------------------------------------------------
  function fmt(v) {
    if (v === null || v === undefined) return "";
    if (typeof v !== "number") return String(v);
    if (Math.abs(v) >= 1e4 || (v !== 0 && Math.abs(v) < 1e-3)) return v.toExponential(2);
    return Number.isInteger(v) ? String(v) : v.toFixed(3);
  }
  function el(parent, tag, cls, text) {
    var e = document.createElement(tag);
    if (cls) e.className = cls;
    if (text !== undefined) e.textContent = text;
    if (parent) parent.appendChild(e);
    return e;
  }
  function clear(node) {
    while (node.firstChild) node.removeChild(node.firstChild);
  }
  function sequence(which) {
    var s = data.sequences || {};
    if (which === "cols" && s.cols === "rows") return s.rows;
    return s[which];
  }
  // A figure with the thumbnail of frame k of a sequence, or a note saying why there is none.
  function thumbnail(parent, seq, k, caption) {
    var figure = el(parent, "figure", "thumb-figure");
    var uri = seq && seq.thumbnails ? seq.thumbnails[k] : null;
    if (uri) {
      var img = el(figure, "img", "thumb");
      img.setAttribute("alt", caption);
      img.setAttribute("data-image", String(k));
      img.setAttribute("src", uri);
    } else {
      el(figure, "div", "no-thumb", seq && seq.note ? seq.note : "no image");
    }
    var name = seq && seq.names && seq.names[k] ? " (" + seq.names[k] + ")" : "";
    el(figure, "figcaption", null, caption + name);
    return figure;
  }
  function keyValues(parent, rows) {
    var table = el(parent, "table", "kv");
    rows.forEach(function (r) {
      var tr = el(table, "tr");
      el(tr, "th", null, r[0]);
      el(tr, "td", null, fmt(r[1]));
    });
    return table;
  }
  function translate(x, y) {
    return "translate(" + x + "," + y + ")";
  }

  // ---- the pair viewer: two images side by side ----------------------------------------------------------
  var viewer = document.getElementById("pair-viewer");
  var pinned = null;
  function showPair(pair, how) {
    if (!viewer) return;
    if (pinned && how !== "pin") return;
    clear(viewer);
    var p = data.pairs;
    var head = el(viewer, "div", "pair-title");
    head.textContent = pair.kind === "cell"
      ? "Cell (" + pair.i + ", " + pair.j + "): " + p.row_name + " " + pair.i + " and " + p.col_name + " " + pair.j
      : p.singular + " " + p.row_name + " " + pair.i + " \u2194 " + p.col_name + " " + pair.j +
        (pinned ? " (pinned: click it again or the matrix to release)" : " (click to pin)");
    var row = el(viewer, "div", "thumb-row");
    thumbnail(row, sequence("rows"), pair.i, p.row_name + " " + pair.i);
    thumbnail(row, sequence("cols"), pair.j, p.col_name + " " + pair.j);
    if (pair.kind !== "cell") {
      keyValues(viewer, p.fields.map(function (f) { return [f.label, pair[f.key]]; }));
    }
    viewer.setAttribute("data-i", String(pair.i));
    viewer.setAttribute("data-j", String(pair.j));
    viewer.setAttribute("data-kind", pair.kind || "pair");
  }
  api.showPair = showPair;

  // ---- the matrix: zoomable, alignments and pairs over it ------------------------------------------------
  function matrixView() {
    var host = document.getElementById("matrix-view");
    var m = data.matrix;
    if (!host || !m) return null;
    var margin = {left: 62, top: 12, right: 110, bottom: 46};
    var W = 520, H = Math.max(120, Math.min(700, Math.round(W * m.rows / m.cols)));
    if (m.rows > m.cols) { H = 520; W = Math.max(120, Math.round(H * m.cols / m.rows)); }
    var x = d3.scale.linear().domain([0, m.cols]).range([0, W]);
    var y = d3.scale.linear().domain([0, m.rows]).range([0, H]);
    var svg = d3.select(host).append("svg").attr("id", "matrix-svg").attr("class", data.kind)
      .attr("width", W + margin.left + margin.right).attr("height", H + margin.top + margin.bottom);
    svg.append("defs").append("clipPath").attr("id", "matrix-clip").append("rect").attr("width", W).attr("height", H);
    var g = svg.append("g").attr("transform", translate(margin.left, margin.top));
    var plot = g.append("g").attr("clip-path", "url(#matrix-clip)");
    var layer = plot.append("g").attr("class", "zoom-layer");
    layer.append("image").attr("class", "matrix-image").attr("width", W).attr("height", H)
      .attr("preserveAspectRatio", "none").attr("xlink:href", m.image);
    var cx = function (j) { return x.range()[0] + (j + 0.5) * W / m.cols; };
    var cy = function (i) { return (i + 0.5) * H / m.rows; };
    var line = d3.svg.line().x(function (p) { return cx(p[1]); }).y(function (p) { return cy(p[0]); });
    layer.selectAll("path.alignment").data(data.alignments || []).enter().append("path")
      .attr("class", function (a) { return "alignment " + (a.kept ? "kept" : "pruned") + " " + a.direction; })
      .attr("d", function (a) { return line(a.path); })
      .append("title").text(function (a) {
        return "alignment " + a.id + " (" + a.direction + (a.kept ? ", kept" : ", pruned") + "): score " + fmt(a.score);
      });
    var pairs = (data.pairs && data.pairs.rows) || [];
    var drawn = pairs.length > 20000 ? pairs.filter(function (p, k) { return k % Math.ceil(pairs.length / 20000) === 0; }) : pairs;
    var markers = layer.selectAll("circle.pair").data(drawn).enter().append("circle")
      .attr("class", "pair " + (data.pairs ? data.pairs.css : ""))
      .attr("cx", function (p) { return cx(p.j); }).attr("cy", function (p) { return cy(p.i); }).attr("r", 3)
      .attr("data-i", function (p) { return p.i; }).attr("data-j", function (p) { return p.j; });
    // With ground truth: false positives and missed revisits as hollow squares (map.json's errors).
    var errors = [];
    if (data.errors) {
      data.errors.false_positives.forEach(function (e) { errors.push({i: e[0], j: e[1], kind: "fp", score: e[2]}); });
      data.errors.missed.forEach(function (e) { errors.push({i: e[0], j: e[1], kind: "miss"}); });
    }
    var errorSide = Math.max(3, 2 * Math.max(m.rows, m.cols) / 120);
    var errorMarks = layer.selectAll("rect.error").data(errors).enter().append("rect")
      .attr("class", function (e) { return "error " + e.kind; })
      .attr("x", function (e) { return cx(e.j) - errorSide * W / m.cols / 2; })
      .attr("y", function (e) { return cy(e.i) - errorSide * H / m.rows / 2; })
      .attr("width", errorSide * W / m.cols).attr("height", errorSide * H / m.rows)
      .attr("data-i", function (e) { return e.i; }).attr("data-j", function (e) { return e.j; });
    errorMarks.append("title").text(function (e) {
      return (e.kind === "fp" ? "false positive: " : "missed revisit: ") + "image " + e.i + " and image " + e.j;
    });
    var crosshair = plot.append("rect").attr("class", "cell-cursor").attr("width", 0).attr("height", 0);

    var xAxis = d3.svg.axis().scale(x).orient("bottom").ticks(7).tickFormat(d3.format("d"));
    var yAxis = d3.svg.axis().scale(y).orient("left").ticks(7).tickFormat(d3.format("d"));
    var gx = g.append("g").attr("class", "axis x").attr("transform", translate(0, H));
    var gy = g.append("g").attr("class", "axis y");
    g.append("text").attr("class", "axis-label").attr("x", W / 2).attr("y", H + 38).attr("text-anchor", "middle")
      .text(m.col_label);
    g.append("text").attr("class", "axis-label").attr("transform", "translate(-46," + H / 2 + ")rotate(-90)")
      .attr("text-anchor", "middle").text(m.row_label);
    g.append("rect").attr("class", "frame").attr("width", W).attr("height", H);

    // Colour bar: the grey levels of the image, black = range[0], white = range[1].
    var gradient = svg.select("defs").append("linearGradient").attr("id", "matrix-gradient")
      .attr("x1", 0).attr("y1", 1).attr("x2", 0).attr("y2", 0);
    gradient.append("stop").attr("offset", "0").attr("stop-color", "#000");
    gradient.append("stop").attr("offset", "1").attr("stop-color", "#fff");
    var barH = Math.min(H, 300), bar = g.append("g").attr("class", "colour-bar")
      .attr("transform", translate(W + 18, (H - barH) / 2));
    bar.append("rect").attr("width", 14).attr("height", barH).style("fill", "url(#matrix-gradient)")
      .style("stroke", "#333");
    var v = d3.scale.linear().domain(m.range).range([barH, 0]);
    bar.append("g").attr("class", "axis").attr("transform", translate(14, 0))
      .call(d3.svg.axis().scale(v).orient("right").ticks(5));
    bar.append("text").attr("class", "axis-label").attr("transform", "translate(70," + barH / 2 + ")rotate(90)")
      .attr("text-anchor", "middle").text(m.value_label);

    var maxZoom = Math.max(2, Math.min(m.rows, m.cols) / 6);
    var zoom = d3.behavior.zoom().x(x).y(y).scaleExtent([1, maxZoom]).on("zoom", redraw);
    svg.call(zoom).on("dblclick.zoom", null);

    function clamp() {
      var s = zoom.scale(), t = zoom.translate();
      t[0] = Math.min(0, Math.max(W - W * s, t[0]));
      t[1] = Math.min(0, Math.max(H - H * s, t[1]));
      zoom.translate(t);
    }
    function redraw() {
      clamp();
      var s = zoom.scale(), t = zoom.translate();
      layer.attr("transform", "translate(" + t[0] + "," + t[1] + ")scale(" + s + ")");
      markers.attr("r", Math.max(1.5, 3 / Math.sqrt(s)) / s);
      gx.call(xAxis);
      gy.call(yAxis);
      svg.attr("data-zoom", s.toFixed(3)).attr("data-x-domain", x.domain().map(function (d) { return d.toFixed(2); }).join(","))
        .attr("data-y-domain", y.domain().map(function (d) { return d.toFixed(2); }).join(","));
    }
    function zoomTo(s, centre) {
      var old = zoom.scale(), t = zoom.translate();
      s = Math.max(1, Math.min(maxZoom, s));
      centre = centre || [W / 2, H / 2];
      zoom.scale(s).translate([centre[0] - (centre[0] - t[0]) * s / old, centre[1] - (centre[1] - t[1]) * s / old]);
      redraw();
    }
    // Shows the box [i0, i1) x [j0, j1) of the matrix, as large as fits.
    function zoomToBox(i0, i1, j0, j1) {
      var s = Math.max(1, Math.min(maxZoom, Math.min(m.cols / Math.max(1, j1 - j0), m.rows / Math.max(1, i1 - i0))));
      var px = (j0 + j1) / 2 * W / m.cols, py = (i0 + i1) / 2 * H / m.rows;
      zoom.scale(s).translate([W / 2 - px * s, H / 2 - py * s]);
      redraw();
    }
    redraw();

    // Hover: the nearest pair within 8 pixels, else the cell under the pointer.
    var lastCell = null;
    function pointer() {
      var p = d3.mouse(plot.node());
      var s = zoom.scale(), t = zoom.translate();
      return [(p[0] - t[0]) / s, (p[1] - t[1]) / s, s];
    }
    function nearest(px, py, s) {
      var best = null, bestD = 8 / s;
      for (var k = 0; k < pairs.length; ++k) {
        var d = Math.max(Math.abs(cx(pairs[k].j) - px), Math.abs(cy(pairs[k].i) - py));
        if (d < bestD) { bestD = d; best = pairs[k]; }
      }
      return best;
    }
    function highlight(pair) {
      markers.classed("active", function (p) { return p === pair; });
    }
    svg.on("mousemove.pairs", function () {
      var q = pointer();
      if (q[0] < 0 || q[1] < 0 || q[0] > W || q[1] > H) return;
      var pair = nearest(q[0], q[1], q[2]);
      if (pair) {
        highlight(pair);
        crosshair.attr("width", 0);
        showPair(pair, "hover");
        return;
      }
      var i = Math.floor(q[1] / H * m.rows), j = Math.floor(q[0] / W * m.cols);
      if (i < 0 || j < 0 || i >= m.rows || j >= m.cols) return;
      var t = zoom.translate(), s = zoom.scale();
      crosshair.attr("x", t[0] + j * W / m.cols * s).attr("y", t[1] + i * H / m.rows * s)
        .attr("width", W / m.cols * s).attr("height", H / m.rows * s);
      document.getElementById("matrix-readout").textContent = data.pairs.row_name + " " + i + ", " +
        data.pairs.col_name + " " + j + " (click to see the two images)";
      lastCell = {kind: "cell", i: i, j: j};
    });
    // A click pins a pair (a second click releases it); a click on any other cell shows its two images.
    svg.on("click.pairs", function () {
      if (d3.event.defaultPrevented) return;  // the end of a drag
      var q = pointer(), pair = nearest(q[0], q[1], q[2]);
      var was = pinned;
      pinned = null;
      markers.classed("pinned", false);
      if (pair && pair !== was) {
        pinned = pair;
        markers.classed("pinned", function (p) { return p === pair; });
        showPair(pair, "pin");
      } else if (pair) {
        showPair(pair, "hover");
      } else if (lastCell) {
        showPair(lastCell, "hover");
      }
    });
    d3.select("#matrix-zoom-in").on("click", function () { zoomTo(zoom.scale() * 2); });
    d3.select("#matrix-zoom-out").on("click", function () { zoomTo(zoom.scale() / 2); });
    d3.select("#matrix-zoom-reset").on("click", function () { zoom.scale(1).translate([0, 0]); redraw(); });
    return {
      zoom: zoomTo, zoomToBox: zoomToBox,
      scale: function () { return zoom.scale(); },
      domain: function () { return {x: x.domain(), y: y.domain()}; },
      pairs: pairs
    };
  }

  // ---- alignments table: a click zooms the matrix to the alignment ---------------------------------------
  function alignmentTable(matrix) {
    var host = document.getElementById("alignment-table");
    if (!host || !data.alignments || !data.alignments.length) return;
    var table = el(host, "table", "alignments");
    var head = el(table, "tr");
    ["#", "direction", "kept", "score", data.pairs.row_name + "s", data.pairs.col_name + "s", "pairs"].forEach(
      function (h) { el(head, "th", null, h); });
    data.alignments.slice(0, 200).forEach(function (a) {
      var tr = el(table, "tr", "alignment-row");
      [a.id, a.direction, a.kept ? "yes" : "no", a.score, a.a[0] + "\u2013" + (a.a[1] - 1),
       a.b[0] + "\u2013" + (a.b[1] - 1), a.pairs].forEach(function (v) { el(tr, "td", null, fmt(v)); });
      tr.addEventListener("click", function () {
        if (matrix) matrix.zoomToBox(a.a[0] - 5, a.a[1] + 5, Math.min(a.b[0], a.b[1]) - 5, Math.max(a.b[0], a.b[1]) + 5);
      });
    });
    if (data.alignments.length > 200) el(host, "p", "note", "The 200 best of " + data.alignments.length + " alignments.");
  }

  // ---- topology: places and junctions, clickable -----------------------------------------------------------
  function topologyView() {
    var host = document.getElementById("topology-view");
    var t = data.topology;
    if (!host || !t) return null;
    var W = 640, H = 480;
    var nodes = t.nodes.map(function (n, k) {
      var a = 2 * Math.PI * k / Math.max(1, t.nodes.length);
      return {id: n.id, kind: n.kind, places: n.places, images: n.images, label: n.label,
              x: W / 2 + 0.38 * W * Math.cos(a), y: H / 2 + 0.38 * H * Math.sin(a)};
    });
    var links = t.links.map(function (l) { return {source: l[0], target: l[1], places: l[2] || 0}; });
    var force = d3.layout.force().nodes(nodes).links(links).size([W, H])
      .charge(nodes.length > 150 ? -25 : -90).linkDistance(nodes.length > 150 ? 10 : 22).gravity(0.08);
    force.start();
    for (var k = 0; k < 300; ++k) force.tick();
    force.stop();
    var svg = d3.select(host).append("svg").attr("id", "topology-svg").attr("width", W).attr("height", H);
    var g = svg.append("g");
    svg.call(d3.behavior.zoom().scaleExtent([0.5, 12]).on("zoom", function () {
      g.attr("transform", "translate(" + d3.event.translate + ")scale(" + d3.event.scale + ")");
    })).on("dblclick.zoom", null);
    g.selectAll("line.edge").data(links).enter().append("line").attr("class", "edge")
      .attr("x1", function (l) { return l.source.x; }).attr("y1", function (l) { return l.source.y; })
      .attr("x2", function (l) { return l.target.x; }).attr("y2", function (l) { return l.target.y; });
    var radius = function (n) { return n.kind === "junction" ? 7 : n.kind === "run" ? 5 : n.images > 1 ? 4.5 : 3; };
    var node = g.selectAll("circle.node").data(nodes).enter().append("circle")
      .attr("class", function (n) { return "node " + n.kind + (n.images > n.places.length ? " revisited" : ""); })
      .attr("cx", function (n) { return n.x; }).attr("cy", function (n) { return n.y; }).attr("r", radius)
      .attr("data-node", function (n, k) { return k; });
    node.append("title").text(function (n) { return n.label; });
    node.on("click", function (n) {
      node.classed("selected", function (o) { return o === n; });
      showNode(n);
    });
    var panel = document.getElementById("place-viewer");
    function showNode(n) {
      if (!panel) return;
      clear(panel);
      el(panel, "div", "pair-title", n.label);
      panel.setAttribute("data-kind", n.kind);
      var images = [];
      n.places.forEach(function (p) { (t.places[p] || []).forEach(function (i) { images.push(i); }); });
      images.sort(function (a, b) { return a - b; });
      var rows = [["places", n.places.length > 6 ? n.places[0] + " \u2026 " + n.places[n.places.length - 1] +
                   " (" + n.places.length + ")" : n.places.join(", ")], ["images", images.length]];
      if (n.kind === "junction") {
        var j = (t.junctions || []).filter(function (x) { return x.place === n.places[0]; })[0];
        var neighbours = links.filter(function (l) { return l.source === n || l.target === n; })
          .map(function (l) { return (l.source === n ? l.target : l.source).label; });
        rows.push(["connects", neighbours.join("; ")]);
        if (j && j.evidence) Object.keys(j.evidence).forEach(function (key) { rows.push([key, j.evidence[key]]); });
      }
      keyValues(panel, rows);
      var strip = el(panel, "div", "thumb-row");
      var step = Math.max(1, Math.ceil(images.length / 12));
      for (var k = 0; k < images.length; k += step) thumbnail(strip, sequence("rows"), images[k], "image " + images[k]);
    }
    var legend = d3.select(host).append("div").attr("class", "legend");
    [["junction", "junction"], ["revisited place", "place revisited"], ["place seen once", "place"],
     ["run of places along a path segment", "run"]].forEach(function (e) {
      if (e[1] === "run" && !t.collapsed) return;
      var item = legend.append("span");
      item.append("svg").attr("width", 14).attr("height", 14).append("circle").attr("cx", 7).attr("cy", 7).attr("r", 5)
        .attr("class", "node " + e[1]);
      item.append("span").text(" " + e[0]);
    });
    return {nodes: nodes, select: function (k) { showNode(nodes[k]); }};
  }

  // ---- line chart of PR curves, with the values under the pointer -----------------------------------------
  function prView() {
    var host = document.getElementById("pr-view");
    if (!host || !data.pr) return;
    var margin = {left: 56, top: 10, right: 16, bottom: 40}, W = 460, H = 320;
    var x = d3.scale.linear().domain([0, 1.02]).range([0, W]);
    var y = d3.scale.linear().domain([0, 1.05]).range([H, 0]);
    var svg = d3.select(host).append("svg").attr("id", "pr-svg")
      .attr("width", W + margin.left + margin.right).attr("height", H + margin.top + margin.bottom);
    var g = svg.append("g").attr("transform", translate(margin.left, margin.top));
    g.append("g").attr("class", "axis").attr("transform", translate(0, H)).call(d3.svg.axis().scale(x).orient("bottom").ticks(5));
    g.append("g").attr("class", "axis").call(d3.svg.axis().scale(y).orient("left").ticks(5));
    g.append("text").attr("class", "axis-label").attr("x", W / 2).attr("y", H + 34).attr("text-anchor", "middle").text("recall");
    g.append("text").attr("class", "axis-label").attr("transform", "translate(-40," + H / 2 + ")rotate(-90)")
      .attr("text-anchor", "middle").text("precision");
    var line = d3.svg.line().x(function (p) { return x(p[0]); }).y(function (p) { return y(p[1]); });
    var curves = data.pr.curves.slice().reverse();  // the method itself last: on top
    g.selectAll("path.curve").data(curves).enter().append("path")
      .attr("class", function (c) { return "curve" + (c.primary ? " primary" : " baseline"); })
      .style("stroke", function (c) { return c.colour; }).attr("d", function (c) { return line(c.points); });
    var dots = g.selectAll("circle.readout").data(curves).enter().append("circle").attr("class", "readout").attr("r", 4)
      .style("fill", function (c) { return c.colour; }).style("display", "none");
    var readout = document.getElementById("pr-readout");
    var legend = d3.select(host).append("div").attr("class", "legend");
    data.pr.curves.forEach(function (c) {
      var item = legend.append("span");
      item.append("svg").attr("width", 26).attr("height", 10).append("line").attr("x1", 0).attr("x2", 26).attr("y1", 5)
        .attr("y2", 5).attr("class", "curve" + (c.primary ? " primary" : " baseline")).style("stroke", c.colour);
      item.append("span").text(" " + c.label + "  ");
    });
    g.append("rect").attr("class", "overlay").attr("width", W).attr("height", H).on("mousemove", function () {
      var r = x.invert(d3.mouse(this)[0]), lines = [];
      dots.each(function (c) {
        var best = null;
        c.points.forEach(function (p) { if (!best || Math.abs(p[0] - r) < Math.abs(best[0] - r)) best = p; });
        if (!best) return;
        d3.select(this).style("display", null).attr("cx", x(best[0])).attr("cy", y(best[1]));
        lines.push(c.label + ": threshold " + fmt(best[2]) + " \u2192 precision " + fmt(best[1]) + ", recall " + fmt(best[0]));
      });
      if (readout) readout.textContent = lines.reverse().join(" | ");
    });
  }

  // ---- histogram of the pairs' confidence -----------------------------------------------------------------
  function histogramView() {
    var host = document.getElementById("confidence-view");
    var h = data.histogram;
    if (!host || !h || !h.values.length) return;
    var margin = {left: 50, top: 10, right: 16, bottom: 40}, W = 460, H = 220;
    var lo = d3.min(h.values), hi = d3.max(h.values);
    if (hi === lo) hi = lo + 1;
    var x = d3.scale.linear().domain([lo, hi]).range([0, W]).nice();
    var bins = d3.layout.histogram().bins(x.ticks(30))(h.values);
    var y = d3.scale.linear().domain([0, d3.max(bins, function (b) { return b.y; })]).range([H, 0]).nice();
    var svg = d3.select(host).append("svg").attr("id", "confidence-svg")
      .attr("width", W + margin.left + margin.right).attr("height", H + margin.top + margin.bottom);
    var g = svg.append("g").attr("transform", translate(margin.left, margin.top));
    var readout = document.getElementById("confidence-readout");
    g.selectAll("rect.bin").data(bins).enter().append("rect").attr("class", "bin")
      .attr("x", function (b) { return x(b.x) + 0.5; }).attr("y", function (b) { return y(b.y); })
      .attr("width", function (b) { return Math.max(1, x(b.x + b.dx) - x(b.x) - 1); })
      .attr("height", function (b) { return H - y(b.y); })
      .on("mouseover", function (b) {
        d3.select(this).classed("active", true);
        if (readout) readout.textContent = h.label + " " + fmt(b.x) + " to " + fmt(b.x + b.dx) + ": " + b.y + " " + h.unit;
      })
      .on("mouseout", function () { d3.select(this).classed("active", false); });
    g.append("g").attr("class", "axis").attr("transform", translate(0, H)).call(d3.svg.axis().scale(x).orient("bottom").ticks(6));
    g.append("g").attr("class", "axis").call(d3.svg.axis().scale(y).orient("left").ticks(5));
    g.append("text").attr("class", "axis-label").attr("x", W / 2).attr("y", H + 34).attr("text-anchor", "middle").text(h.label);
    g.append("text").attr("class", "axis-label").attr("transform", "translate(-38," + H / 2 + ")rotate(-90)")
      .attr("text-anchor", "middle").text(h.unit);
  }

  // ---- stage timings as one bar that adds up to the wall time ----------------------------------------------
  function timingsView() {
    var host = document.getElementById("timings-view");
    var t = data.timings;
    if (!host || !t || !t.rows.length) return;
    var W = 640, H = 26, total = t.wall || d3.sum(t.rows, function (r) { return r[1]; });
    var x = d3.scale.linear().domain([0, total]).range([0, W]);
    var colour = d3.scale.category20();
    var svg = d3.select(host).append("svg").attr("id", "timings-svg").attr("width", W + 2).attr("height", H + 24);
    var start = 0, parts = t.rows.map(function (r) { var p = {name: r[0], seconds: r[1], start: start}; start += r[1]; return p; });
    var readout = document.getElementById("timings-readout");
    svg.selectAll("rect").data(parts).enter().append("rect").attr("class", "stage")
      .attr("x", function (p) { return 1 + x(p.start); }).attr("y", 1)
      .attr("width", function (p) { return Math.max(0.5, x(p.seconds)); }).attr("height", H)
      .style("fill", function (p, k) { return colour(k); })
      .on("mouseover", function (p) {
        if (readout) readout.textContent = p.name + ": " + p.seconds.toFixed(3) + " s (" + (100 * p.seconds / total).toFixed(1) + " %)";
      });
    svg.append("g").attr("class", "axis").attr("transform", translate(1, H + 2))
      .call(d3.svg.axis().scale(x).orient("bottom").ticks(8).tickFormat(function (s) { return s + " s"; }));
  }

  var matrix = matrixView();
  api.matrix = matrix;
  alignmentTable(matrix);
  api.topology = topologyView();
  prView();
  histogramView();
  timingsView();
  document.body.setAttribute("data-interactive", "ready");
})();
