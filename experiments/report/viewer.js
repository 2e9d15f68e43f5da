// The report's image viewer: flip between the reference and each
// configuration's final image, zoom and pan, and set the exposure on the
// linear data (after SeeSharp's FlipBook). report.py inlines this file into
// report.html, so it must work offline and stand alone: no libraries.
//
// Data: each <div class="lb-viewer" data-source="ID"> names a
// <script type="application/json" id="ID"> holding
//   {width, height, downsample, source: "exr" | "png", epsilon, crop,
//    images: [{name, data}]}
// where data is base64 of little-endian IEEE half floats, RGB, rows top to
// bottom, and images[0] is the reference.
(function () {
  'use strict';

  // Every half float's value, so decoding is one lookup per channel.
  const HALF = (function () {
    const t = new Float32Array(65536);
    for (let h = 0; h < 65536; h++) {
      const s = h & 0x8000 ? -1 : 1, e = (h >> 10) & 0x1f, m = h & 0x3ff;
      t[h] = e === 0 ? s * m * Math.pow(2, -24)
           : e === 31 ? (m ? NaN : s * Infinity)
           : s * (1 + m / 1024) * Math.pow(2, e - 15);
    }
    return t;
  })();

  // sRGB encoding of [0, 1] in 4096 steps: finer than the 8-bit output.
  const SRGB = (function () {
    const t = new Uint8ClampedArray(4096);
    for (let i = 0; i < 4096; i++) {
      const v = i / 4095;
      t[i] = Math.round(255 * (v <= 0.0031308 ? 12.92 * v : 1.055 * Math.pow(v, 1 / 2.4) - 0.055));
    }
    return t;
  })();

  // The runner's false colour (experiments/metrics.cpp falseColour): five
  // stops of viridis over log10 of the relative squared error, 1e-4 to 10.
  const VIRIDIS = [[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]];
  const ERR_LO = -4, ERR_HI = 1;

  function decode(b64) {
    const bin = atob(b64), n = bin.length >> 1, out = new Float32Array(n);
    for (let i = 0; i < n; i++) out[i] = HALF[bin.charCodeAt(2 * i) | (bin.charCodeAt(2 * i + 1) << 8)];
    return out;
  }

  function el(tag, cls, text) {
    const e = document.createElement(tag);
    if (cls) e.className = cls;
    if (text !== undefined) e.textContent = text;
    return e;
  }

  let active = null;  // the viewer that keys go to

  class Viewer {
    constructor(root, data) {
      this.root = root;
      this.w = data.width;
      this.h = data.height;
      this.data = data;
      this.images = data.images.map(im => ({ name: im.name, px: decode(im.data) }));
      for (const im of this.images)
        if (im.px.length !== this.w * this.h * 3) throw new Error('viewer: ' + im.name + ' has the wrong size');
      this.current = this.images.length > 1 ? 1 : 0;
      this.previous = 0;
      this.exposure = 0;
      this.errorMode = false;
      this.showCrop = !!data.crop;
      this.build();
      this.fit();
      this.render();
    }

    build() {
      const r = this.root;
      r.tabIndex = 0;
      const bar = el('div', 'lbv-buttons');
      this.buttons = this.images.map((im, i) => {
        const b = el('button', 'lbv-button');
        if (i < 10) b.appendChild(el('kbd', null, String((i + 1) % 10)));
        b.appendChild(document.createTextNode(' ' + im.name));
        b.addEventListener('click', () => this.select(i));
        bar.appendChild(b);
        return b;
      });
      const controls = el('div', 'lbv-controls');
      const exp = el('label', null, 'exposure ');
      this.slider = el('input');
      Object.assign(this.slider, { type: 'range', min: -10, max: 10, step: 0.1, value: 0 });
      this.slider.addEventListener('input', () => this.setExposure(parseFloat(this.slider.value)));
      this.expText = el('span', 'lbv-ev', '+0.0 stops');
      exp.append(this.slider, this.expText);
      const err = el('label');
      this.errBox = el('input');
      this.errBox.type = 'checkbox';
      this.errBox.addEventListener('change', () => { this.errorMode = this.errBox.checked; this.render(); });
      err.append(this.errBox, ' rel. squared error (e)');
      const fitB = el('button', null, 'fit (f)');
      fitB.addEventListener('click', () => { this.fit(); this.draw(); });
      controls.append(exp, err, fitB);
      if (this.data.crop) {
        const cropB = el('button', null, 'zoom to crop (c)');
        cropB.addEventListener('click', () => this.zoomToCrop());
        controls.append(cropB);
      }
      const stage = el('div', 'lbv-stage');
      this.canvas = el('canvas');
      const maxW = Math.min(768, Math.max(320, r.clientWidth || 768)), maxH = 640;
      const s = Math.min(maxW / this.w, maxH / this.h);
      this.canvas.width = Math.round(this.w * s);
      this.canvas.height = Math.round(this.h * s);
      this.ctx = this.canvas.getContext('2d');
      this.nameTag = el('div', 'lbv-name');
      stage.append(this.canvas, this.nameTag);
      this.status = el('div', 'lbv-status', '\u00a0');
      r.append(bar, controls, stage, this.status);
      // The image at its own resolution; drawn scaled onto the visible canvas.
      this.off = el('canvas');
      this.off.width = this.w;
      this.off.height = this.h;
      this.offCtx = this.off.getContext('2d');
      this.buffer = this.offCtx.createImageData(this.w, this.h);
      this.events();
    }

    events() {
      const c = this.canvas;
      const pos = e => {
        const b = c.getBoundingClientRect();
        return [(e.clientX - b.left) * c.width / b.width, (e.clientY - b.top) * c.height / b.height];
      };
      c.addEventListener('wheel', e => {
        e.preventDefault();
        const [mx, my] = pos(e), z = this.zoom;
        const nz = Math.min(64, Math.max(this.fitZoom / 4, z * (e.deltaY < 0 ? 1.25 : 0.8)));
        this.ox = mx - (mx - this.ox) * nz / z;
        this.oy = my - (my - this.oy) * nz / z;
        this.zoom = nz;
        this.draw();
      }, { passive: false });
      let drag = null;
      c.addEventListener('pointerdown', e => {
        drag = { x: e.clientX, y: e.clientY, ox: this.ox, oy: this.oy, moved: false };
        c.setPointerCapture(e.pointerId);
      });
      c.addEventListener('pointermove', e => {
        if (drag) {
          const b = c.getBoundingClientRect(), k = c.width / b.width;
          const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
          if (Math.abs(dx) + Math.abs(dy) > 3) drag.moved = true;
          this.ox = drag.ox + dx * k;
          this.oy = drag.oy + dy * k;
          this.draw();
        }
        this.readout(pos(e));
      });
      c.addEventListener('pointerup', () => {
        // A click without a drag flips back to the image shown before.
        if (drag && !drag.moved) this.select(this.previous);
        drag = null;
      });
      c.addEventListener('dblclick', () => { this.fit(); this.draw(); });
      // Keys go to the viewer under the pointer or holding the focus, so
      // that the arrows still scroll the rest of the page.
      this.root.addEventListener('pointerenter', () => { this.hover = true; active = this; });
      this.root.addEventListener('pointerleave', () => {
        this.hover = false;
        if (active === this && !this.root.contains(document.activeElement)) active = null;
      });
      this.root.addEventListener('focusin', () => { active = this; });
      this.root.addEventListener('focusout', e => {
        if (active === this && !this.hover && !this.root.contains(e.relatedTarget)) active = null;
      });
    }

    select(i) {
      if (i < 0 || i >= this.images.length || i === this.current) return;
      this.previous = this.current;
      this.current = i;
      this.render();
    }

    setExposure(v) {
      this.exposure = Math.max(-10, Math.min(10, Math.round(v * 10) / 10));
      this.slider.value = this.exposure;
      this.expText.textContent = (this.exposure >= 0 ? '+' : '') + this.exposure.toFixed(1) + ' stops';
      if (!this.errorMode) this.render();
    }

    fit() {
      this.fitZoom = Math.min(this.canvas.width / this.w, this.canvas.height / this.h);
      this.zoom = this.fitZoom;
      this.ox = (this.canvas.width - this.w * this.zoom) / 2;
      this.oy = (this.canvas.height - this.h * this.zoom) / 2;
    }

    zoomToCrop() {
      const [x0, y0, x1, y1] = this.data.crop;
      this.zoom = Math.min(this.canvas.width / (x1 - x0), this.canvas.height / (y1 - y0));
      this.ox = (this.canvas.width - (x0 + x1) * this.zoom) / 2;
      this.oy = (this.canvas.height - (y0 + y1) * this.zoom) / 2;
      this.draw();
    }

    // The per-pixel relative squared error against the reference, averaged
    // over RGB as the runner's error images and relMSE are.
    relError(px, ref, i) {
      let e = 0;
      for (let c = 0; c < 3; c++) {
        const d = px[i + c] - ref[i + c];
        e += d * d / (ref[i + c] * ref[i + c] + this.data.epsilon);
      }
      return e / 3;
    }

    render() {
      const px = this.images[this.current].px, ref = this.images[0].px, d = this.buffer.data;
      const scale = Math.pow(2, this.exposure), n = this.w * this.h;
      for (let p = 0, i = 0, o = 0; p < n; p++, i += 3, o += 4) {
        if (this.errorMode) {
          const e = this.relError(px, ref, i);
          const v = Number.isFinite(e) ? Math.log10(Math.max(e, 1e-30)) : ERR_HI;
          const t = Math.min(1, Math.max(0, (v - ERR_LO) / (ERR_HI - ERR_LO))) * 4, k = Math.min(3, Math.floor(t));
          for (let c = 0; c < 3; c++) d[o + c] = VIRIDIS[k][c] + (VIRIDIS[k + 1][c] - VIRIDIS[k][c]) * (t - k);
        } else if (Number.isFinite(px[i]) && Number.isFinite(px[i + 1]) && Number.isFinite(px[i + 2])) {
          for (let c = 0; c < 3; c++) d[o + c] = SRGB[Math.round(Math.min(1, Math.max(0, px[i + c] * scale)) * 4095)];
        } else {
          d[o] = 255; d[o + 1] = 0; d[o + 2] = 255;  // NaN or Inf: magenta
        }
        d[o + 3] = 255;
      }
      this.offCtx.putImageData(this.buffer, 0, 0);
      this.buttons.forEach((b, i) => b.classList.toggle('lbv-on', i === this.current));
      const im = this.images[this.current];
      this.nameTag.textContent = im.name + (this.errorMode ? ' \u2014 relative squared error' : '');
      this.draw();
    }

    draw() {
      const ctx = this.ctx;
      ctx.setTransform(1, 0, 0, 1, 0, 0);
      ctx.fillStyle = '#222';
      ctx.fillRect(0, 0, this.canvas.width, this.canvas.height);
      ctx.imageSmoothingEnabled = false;
      ctx.setTransform(this.zoom, 0, 0, this.zoom, this.ox, this.oy);
      ctx.drawImage(this.off, 0, 0);
      if (this.showCrop && this.data.crop) {
        const [x0, y0, x1, y1] = this.data.crop;
        ctx.strokeStyle = '#ff3b30';
        ctx.lineWidth = 1.5 / this.zoom;
        ctx.strokeRect(x0, y0, x1 - x0, y1 - y0);
      }
    }

    readout([mx, my]) {
      const x = Math.floor((mx - this.ox) / this.zoom), y = Math.floor((my - this.oy) / this.zoom);
      if (x < 0 || y < 0 || x >= this.w || y >= this.h) { this.status.textContent = '\u00a0'; return; }
      const i = 3 * (y * this.w + x), px = this.images[this.current].px, ref = this.images[0].px;
      const f = v => (Number.isFinite(v) ? v.toPrecision(4) : String(v));
      const ds = this.data.downsample;
      const where = ds > 1 ? `pixel ${x}, ${y} (full resolution ${x * ds}\u2013${x * ds + ds - 1}, ${y * ds}\u2013${y * ds + ds - 1})`
                           : `pixel ${x}, ${y}`;
      this.status.textContent = `${where}   RGB ${f(px[i])} ${f(px[i + 1])} ${f(px[i + 2])}` +
        (this.current ? `   relative squared error ${f(this.relError(px, ref, i))}` : '   (reference)');
    }

    key(e) {
      const k = e.key;
      if (k >= '0' && k <= '9') this.select((Number(k) + 9) % 10);
      else if (k === 'ArrowRight') this.select((this.current + 1) % this.images.length);
      else if (k === 'ArrowLeft') this.select((this.current + this.images.length - 1) % this.images.length);
      else if (k === 'e') { this.errBox.checked = this.errorMode = !this.errorMode; this.render(); }
      else if (k === 'f') { this.fit(); this.draw(); }
      else if (k === 'c' && this.data.crop) this.zoomToCrop();
      else if (k === '+' || k === '=') this.setExposure(this.exposure + 0.5);
      else if (k === '-') this.setExposure(this.exposure - 0.5);
      else return;
      e.preventDefault();
    }
  }

  document.addEventListener('keydown', e => {
    if (!active || e.ctrlKey || e.metaKey || e.altKey) return;
    if (/^(INPUT|SELECT|TEXTAREA)$/.test(e.target.tagName) && e.target.type !== 'checkbox') return;
    active.key(e);
  });

  for (const root of document.querySelectorAll('.lb-viewer')) {
    const source = document.getElementById(root.dataset.source);
    const v = new Viewer(root, JSON.parse(source.textContent));
    console.log('viewer ready ' + v.images.length + ' images');
  }
})();
