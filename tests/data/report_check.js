// Injected into a report page by tests/browser.py: after load, every <figure> is checked as
// Chromium drew it, and the answer is written as JSON into a pre element, id colonna-check.
//   image figures: decoded and shown with a non-zero size;
//   SVG figures (matplotlib, text kept as text): shown with a non-zero size, at least one data
//   artist drawn (a line, collection or filled patch of an axes, not ticks, spines, frames);
//   every legend entry the report lists (data-legend) is a legend text drawn inside the figure;
//   every legend handle's colour is the colour of a drawn data artist of the same figure.
window.addEventListener('load', () => {
  const area = el => { const b = el.getBoundingClientRect(); return b.width * b.height; };
  const extent = el => { const b = el.getBoundingClientRect(); return b.width + b.height; };  // a line has no area
  const within = (inner, outer) => {
    const a = inner.getBoundingClientRect(), b = outer.getBoundingClientRect();
    return a.left >= b.left - 1 && a.right <= b.right + 1 && a.top >= b.top - 1
      && a.bottom <= b.bottom + 1;
  };
  const colours = el => {
    const found = [];
    for (const node of el.querySelectorAll('path, use, rect, polygon')) {
      if (node.closest('defs')) continue;                 // drawn where it is used
      const style = getComputedStyle(node);
      for (const c of [style.fill, style.stroke]) {
        if (c && c !== 'none' && c !== 'rgb(255, 255, 255)') found.push(c);
      }
    }
    return found;
  };
  const vertices = node => ((node.getAttribute('d') || '').match(/[ML]/g) || []).length;
  const results = [];
  for (const fig of document.querySelectorAll('figure[data-figure]')) {
    const r = {name: fig.dataset.figure, legend: JSON.parse(fig.dataset.legend || '[]'),
               problems: []};
    const img = fig.querySelector('img'), svg = fig.querySelector('svg');
    if (img) {
      if (!(img.complete && img.naturalWidth > 0 && area(img) > 0)) r.problems.push('image not drawn');
    } else if (!svg || area(svg) <= 0) {
      r.problems.push('no figure drawn');
    } else {
      // data artists: direct children of an axes group, other than axis, text and legend groups;
      // of the patches only filled ones that are not the axes background (spines are lines)
      const drawn = new Set();
      let artists = 0;
      for (const axes of svg.querySelectorAll('g[id^="axes_"]')) {
        const children = [...axes.children].filter(g => g.tagName === 'g');
        children.forEach((g, k) => {
          const id = g.id || '';
          if (/^(matplotlib\.axis|text_|legend_)/.test(id)) return;
          if (id.startsWith('patch_')) {
            if (k === 0) return;                                  // the axes background
            const p = g.querySelector('path');
            const fill = p ? getComputedStyle(p).fill : 'none';
            if (!p || fill === 'none' || fill === 'rgb(255, 255, 255)' || vertices(p) <= 2) return;
          }
          const cs = colours(g);
          if (cs.length && extent(g) > 0) { artists += 1; cs.forEach(c => drawn.add(c)); }
        });
      }
      if (artists === 0) r.problems.push('no data drawn');
      r.artists = artists;
      // legends: texts in order, each after its handle(s)
      const texts = [], handleColours = {};
      for (const legend of svg.querySelectorAll('g[id^="legend_"]')) {
        let pending = [];
        [...legend.children].filter(g => g.tagName === 'g').forEach((g, k) => {
          if (k === 0 && (g.id || '').startsWith('patch_')) return;       // the frame
          if ((g.id || '').startsWith('text_')) {
            // a wrapped entry is a text per line: its label is their words, shown if all are
            const lines = [...g.querySelectorAll('text')];
            const label = lines.map(t => t.textContent).join(' ').split(/\s+/).join(' ').trim();
            texts.push({label, shown: lines.length > 0 &&
                        lines.every(t => area(t) > 0 && within(t, svg))});
            handleColours[label] = pending.flatMap(colours);
            pending = [];
          } else {
            pending.push(g);
          }
        });
      }
      for (const entry of r.legend) {
        const t = texts.find(x => x.label === entry);
        if (!t) { r.problems.push(`legend entry "${entry}" not drawn`); continue; }
        if (!t.shown) r.problems.push(`legend entry "${entry}" outside the figure`);
        const cs = handleColours[entry] || [];
        if (!cs.some(c => drawn.has(c)))
          r.problems.push(`legend entry "${entry}": its colour ${cs.join(' ')} is not drawn`);
      }
      if (texts.length !== r.legend.length) r.problems.push(
        `${texts.length} legend texts drawn, ${r.legend.length} listed`);
    }
    results.push(r);
  }
  const pre = document.createElement('pre');
  pre.id = 'colonna-check';
  pre.textContent = JSON.stringify(results);
  document.body.appendChild(pre);
});
