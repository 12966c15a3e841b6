// Injected by tests/report/html_report_test.cpp into a copy of the report, after its own
// scripts: once plotly has drawn every figure, it reads what the browser drew (plotly's
// resolved traces and the SVG's computed colours) and writes one line per finding into
// a pre element (id ccomp-look), which the test reads from Chromium's --dump-dom:
//   LEGEND <plot> <trace name>: legend <colour> drawn <colour>   a legend entry unlike its curve
//   UNLABELLED <plot> <trace name>                               a trace drawn with no legend entry
//   SCALE <before plot> <after plot>: <zmin..zmax> / <zmin..zmax> a before/after pair on two colour scales
//   TICKS <before plot> <after plot>: <labels> / <labels>       their colour bars labelled apart
//   UNITLESS <plot> <axis>: <title>                              an axis title without a unit
//   CHECKED legends <n> entries <n> pairs <n> axes <n>
window.setTimeout(function () {
  const out = [];
  // A colour as its red, green and blue (opacity aside: plotly draws it as a separate
  // attribute), from a CSS value or an element's computed style; '' for none.
  const probe = document.createElement('span');
  document.body.appendChild(probe);
  const rgb = (css) => {
    if (!css || css === 'none') return '';
    probe.style.color = '';
    probe.style.color = css;
    const m = /rgba?\((\d+), (\d+), (\d+)(, ([\d.]+))?\)/.exec(getComputedStyle(probe).color);
    return m && !(m[5] !== undefined && parseFloat(m[5]) === 0) ? m[1] + ',' + m[2] + ',' + m[3] : '';
  };
  const styled = (el, property) => (el ? rgb(getComputedStyle(el)[property]) : '');
  // What a legend entry's symbol shows: a line (of some width), a marker, a fill swatch.
  const symbol = (item) => {
    const line = item.querySelector('.legendlines path.js-line, path.js-line');
    const width = line ? parseFloat(getComputedStyle(line).strokeWidth) : 0;
    const point = item.querySelector('.legendpoints path.scatterpts, path.scatterpts');
    const fill = item.querySelector('.legendfill path.js-fill, path.js-fill');
    const bar = item.querySelector('.legendpoints path.legendundefined, .legendpoints path.legendbar');
    return {line: width > 0 ? styled(line, 'stroke') : '',
      point: styled(point, 'fill') || styled(point, 'stroke'), fill: styled(fill, 'fill') || styled(bar, 'fill')};
  };
  // What a trace draws, as plotly resolved it: its line, its markers, its fill.
  const drawn = (t) => {
    if (t.type === 'bar') return {line: '', point: '', fill: rgb(t.marker && t.marker.color)};
    const mode = t.mode || '';
    return {line: mode.includes('lines') && t.line && t.line.width > 0 ? rgb(t.line.color) : '',
      point: mode.includes('markers') && t.marker ? rgb(t.marker.color) || rgb(t.marker.line && t.marker.line.color) : '',
      fill: t.fill && t.fill !== 'none' ? rgb(t.fillcolor) : ''};
  };
  const show = (a) => ['line', 'point', 'fill'].filter((k) => a[k]).map((k) => k + ' ' + a[k]).join(', ') || 'nothing';
  let legends = 0, entries = 0, pairs = 0, axes = 0;
  const maps = [];
  for (const gd of document.querySelectorAll('.js-plotly-plot')) {
    const id = gd.id;
    const traces = gd._fullData.filter((t) => t.visible === true && /^(scatter|bar)/.test(t.type));
    if (gd._fullLayout.showlegend) {
      ++legends;
      const labelled = new Set();
      for (const item of gd.querySelectorAll('.legend .traces')) {
        const d = item.__data__ && item.__data__[0] && item.__data__[0].trace;
        if (!d) continue;
        ++entries;
        labelled.add(d.index);
        // The symbol shows what the trace draws, in its colours; a part it does not show
        // (a marker-only entry for a line) is not compared.
        const shown = symbol(item), want = drawn(d);
        const differs = ['line', 'point', 'fill'].some((k) => shown[k] && shown[k] !== want[k]);
        if (differs || show(shown) === 'nothing')
          out.push('LEGEND ' + id + ' ' + d.name + ': legend ' + show(shown) + ' drawn ' + show(want));
      }
      for (const t of traces) {
        const look = drawn(t);
        if (!labelled.has(t.index) && (look.line || look.point || look.fill))
          out.push('UNLABELLED ' + id + ' ' + t.name + ' (' + show(look) + ')');
      }
    }
    // Every Cartesian axis title names a unit, "(um)", "(mm)", "(s)", or says it counts.
    for (const name of Object.keys(gd._fullLayout).filter((k) => /^[xy]axis\d*$/.test(k))) {
      const a = gd._fullLayout[name];
      if (!a.visible) continue;
      ++axes;
      const title = (a.title && a.title.text) || '';
      if (!/\([^)]+\)|file order|combination|relative to the largest/.test(title) && a.type !== 'category')
        out.push('UNITLESS ' + id + ' ' + name + ': ' + title);
    }
    const contour = gd._fullData.find((t) => t.type === 'contour' || t.type === 'heatmap');
    if (contour) {
      const ticks = [...gd.querySelectorAll('.colorbar .cbaxis text')].map((t) => t.textContent);
      maps.push({id, title: gd._fullLayout.title.text, zmin: contour.zmin, zmax: contour.zmax,
        scale: JSON.stringify(contour.colorscale), ticks: ticks.join(' ')});
    }
  }
  // A before map and the after map of the same plane.
  for (const before of maps.filter((m) => m.title.startsWith('Before compensation: '))) {
    const plane = before.title.slice('Before compensation: '.length);
    const after = maps.find((m) => m.title === 'After compensation: ' + plane);
    if (!after) {
      out.push('SCALE ' + before.id + ' (no after map for ' + plane + ')');
      continue;
    }
    ++pairs;
    if (before.zmin !== after.zmin || before.zmax !== after.zmax || before.scale !== after.scale)
      out.push('SCALE ' + before.id + ' ' + after.id + ': ' + before.zmin + '..' + before.zmax + ' / ' + after.zmin +
               '..' + after.zmax);
    if (before.ticks !== after.ticks || !before.ticks)
      out.push('TICKS ' + before.id + ' ' + after.id + ': ' + before.ticks + ' / ' + after.ticks);
  }
  out.push('CHECKED legends ' + legends + ' entries ' + entries + ' pairs ' + pairs + ' axes ' + axes);
  const pre = document.createElement('pre');
  pre.id = 'ccomp-look';
  pre.textContent = out.join('\n');
  document.body.appendChild(pre);
}, 1000);  // after plotly's drawing, in Chromium's virtual time
