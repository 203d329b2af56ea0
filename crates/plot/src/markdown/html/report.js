// The report page's script: sortable tables, the figure menus, and
// the ready flag on <body> (dataset.ready) once it has run. No library, no
// request.
(function () {
  "use strict";
  var NUMBER = /^[+\-\u2212]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+\-\u2212]?\d+)?/;
  var MISSING = { "": 1, "\u2014": 1, "-": 1, "n/a": 1, "NaN": 1 };
  var collator = new Intl.Collator("en", { numeric: true, sensitivity: "base" });

  // A cell's sort key: numbers (a leading number followed by nothing, a
  // percent sign or a space) by value, empty cells last, text in natural order.
  function key(text) {
    var t = text.trim();
    if (MISSING[t]) return { kind: 2, value: 0 };
    if (t === "inf" || t === "+inf") return { kind: 0, value: Infinity };
    if (t === "-inf" || t === "\u2212inf") return { kind: 0, value: -Infinity };
    var m = t.match(NUMBER);
    if (m) {
      var rest = t.slice(m[0].length);
      if (rest === "" || rest === "%" || /^\s/.test(rest)) {
        var v = parseFloat(m[0].replace(/\u2212/g, "-"));
        if (!isNaN(v)) return { kind: 0, value: v };
      }
    }
    return { kind: 1, value: t };
  }

  function compare(a, b) {
    if (a.kind !== b.kind) return a.kind - b.kind;
    if (a.kind === 0) return a.value < b.value ? -1 : a.value > b.value ? 1 : 0;
    if (a.kind === 1) return collator.compare(a.value, b.value);
    return 0;
  }

  function sortBy(table, column, th) {
    var body = table.tBodies[0];
    if (!body) return;
    var descending = th.getAttribute("aria-sort") === "ascending";
    var rows = Array.prototype.map.call(body.rows, function (row, i) {
      var cell = row.cells[column];
      return { row: row, i: i, key: key(cell ? cell.textContent : "") };
    });
    rows.sort(function (a, b) {
      var c = compare(a.key, b.key);
      // Empty cells stay last in either direction.
      if (c !== 0 && a.key.kind !== 2 && b.key.kind !== 2 && descending) c = -c;
      return c !== 0 ? c : a.i - b.i;
    });
    rows.forEach(function (r) { body.appendChild(r.row); });
    Array.prototype.forEach.call(th.parentNode.cells, function (h) {
      h.removeAttribute("aria-sort");
    });
    th.setAttribute("aria-sort", descending ? "descending" : "ascending");
  }

  document.querySelectorAll("table.mb-sortable").forEach(function (table) {
    if (!table.tHead || !table.tHead.rows.length) return;
    Array.prototype.forEach.call(table.tHead.rows[0].cells, function (th, column) {
      th.tabIndex = 0;
      th.title = "Sort by this column";
      th.addEventListener("click", function () { sortBy(table, column, th); });
      th.addEventListener("keydown", function (e) {
        if (e.key === "Enter" || e.key === " ") {
          e.preventDefault();
          sortBy(table, column, th);
        }
      });
    });
  });

  // The figure menus: one unit of the group shown, or all of them.
  function show(select) {
    var group = select.getAttribute("data-group");
    var value = select.value;
    document.querySelectorAll('.mb-unit[data-group="' + group + '"]').forEach(function (unit) {
      var hide = value !== "all" && unit.getAttribute("data-index") !== value;
      unit.classList.toggle("mb-hidden", hide);
    });
  }
  document.querySelectorAll("select.mb-select").forEach(function (select) {
    select.addEventListener("change", function () { show(select); });
    show(select);
  });

  // A link to a hidden figure shows it first.
  function reveal() {
    var id;
    try {
      id = decodeURIComponent(window.location.hash.slice(1));
    } catch (e) {
      return;
    }
    var target = id && document.getElementById(id);
    var unit = target && target.closest(".mb-unit");
    if (!unit || !unit.classList.contains("mb-hidden")) return;
    var select = document.querySelector(
      'select.mb-select[data-group="' + unit.getAttribute("data-group") + '"]');
    if (!select) return;
    select.value = unit.getAttribute("data-index");
    show(select);
    target.scrollIntoView();
  }
  window.addEventListener("hashchange", reveal);
  reveal();

  document.body.dataset.ready = "1";
})();
