/* The acsg report page: summary, graph (cytoscape.js), witness pose (three.js), table.
   Everything it shows comes from the JSON in #acsg-data (format acsg-graph/1). */
(function () {
  'use strict';

  var T0 = performance.now();
  var D = JSON.parse(document.getElementById('acsg-data').textContent);
  var G = D.graph;
  var states = G.states;
  var N = states.length;
  var LARGE = N > 1500;

  // ---------- helpers ----------
  function el(tag, attrs, children) {
    var node = document.createElement(tag);
    if (attrs) {
      Object.keys(attrs).forEach(function (k) {
        if (k === 'text') node.textContent = attrs[k];
        else if (k === 'class') node.className = attrs[k];
        else node.setAttribute(k, attrs[k]);
      });
    }
    (children || []).forEach(function (c) {
      node.appendChild(typeof c === 'string' ? document.createTextNode(c) : c);
    });
    return node;
  }
  function fmt(x, digits) {
    if (x === null || x === undefined) return '';
    var s = Number(x).toFixed(digits === undefined ? 3 : digits);
    return s === '-0.000' || s === '-0.00' || s === '-0.0' ? s.slice(1) : s;
  }
  function deg(r) { return r * 180 / Math.PI; }
  function contactText(c) { return c.type + ' ' + c.fixed + ' × ' + c.moving; }
  var PC_COLOURS = ['#e6194b', '#2f9e44', '#f08c00', '#1c7ed6', '#9c36b5', '#0ca678', '#d6336c', '#5c940d', '#e8590c', '#3b5bdb', '#862e9c', '#495057'];
  function pcColour(k) { return PC_COLOURS[k % PC_COLOURS.length]; }
  // Sequential palette (viridis-like), from few constraints (light) to many (dark).
  var SEQ = ['#fde725', '#90d743', '#35b779', '#21918c', '#31688e', '#443983', '#440154'];
  function seq(t) { return SEQ[Math.max(0, Math.min(SEQ.length - 1, Math.round(t * (SEQ.length - 1))))]; }
  var maxContacts = 0;
  states.forEach(function (s) { maxContacts = Math.max(maxContacts, s.contacts.length); });
  var colourBy = 'dof';
  function stateColour(s) {
    if (colourBy === 'dof') return seq((6 - s.dof) / 6);
    return seq(maxContacts ? s.contacts.length / maxContacts : 0);
  }

  var neighbours = states.map(function () { return []; });
  G.edges.forEach(function (e) { neighbours[e[0]].push(e[1]); neighbours[e[1]].push(e[0]); });

  // ---------- header, summary, footer ----------
  var lengthUnit = (G.units && G.units.length) || 'model units';
  document.getElementById('subtitle').textContent =
    G.fixed.path + ' (fixed) / ' + G.moving.path + ' (moving): ' + N + ' states, ' + G.edges.length + ' edges';
  document.getElementById('footer').textContent =
    'Made by ' + D.generator + ' (format ' + G.format + '). Pose convention: ' + G.convention +
    '. Lengths in ' + lengthUnit + ', angles in degrees on this page (radians in the JSON).';

  function table(rows, header) {
    var t = el('table');
    if (header) t.appendChild(el('tr', null, header.map(function (h) { return el('th', { text: h }); })));
    rows.forEach(function (r) {
      t.appendChild(el('tr', null, r.map(function (cell, i) {
        return el('td', { text: String(cell), class: i > 0 && typeof cell === 'number' ? 'n' : '' });
      })));
    });
    return t;
  }
  (function summary() {
    var box = document.getElementById('summary');
    var s = G.stats;
    var parts = [['', 'faces', 'edges', 'vertices']];
    [['fixed', G.fixed], ['moving', G.moving]].forEach(function (p) {
      parts.push([p[0] + ': ' + p[1].path, p[1].faces.length, p[1].edges.length, p[1].vertices.length]);
    });
    var names = ['x', 'y', 'z', 'rx', 'ry', 'rz'];
    var bounds = names.map(function (n, k) {
      var lo = G.bounds.min[k], hi = G.bounds.max[k];
      return k < 3 ? [n, fmt(lo, 3) + ' … ' + fmt(hi, 3) + ' ' + lengthUnit] : [n, fmt(deg(lo), 2) + '° … ' + fmt(deg(hi), 2) + '°'];
    });
    var stage1 = [
      ['card(PPC)', s.ppc], ['ruled out without optimising', s.ppc_unreachable], ['feasible PPCs', s.feasible_ppc],
      ['searched by optimisation', s.stage1_searched], ['local optimisation runs', s.stage1_optimisations],
      ['time (s)', fmt(s.stage1_seconds, 3)]
    ];
    var stage2 = [
      ['pairs (a state, a contact to add)', s.stage2_pairs],
      ['implied (held already, or the state itself)', s.pruned_implied],
      ['pairs with no outcome (topology)', s.pruned_topology],
      ['outcomes left out as degenerate', s.pruned_degenerate], ['outcomes already known or proposed', s.pruned_duplicate],
      ['new candidates', s.stage2_candidates], ['… ruled out without optimising', s.pruned_unreachable],
      ['… searched by optimisation', s.stage2_searched], ['local optimisation runs', s.stage2_optimisations],
      ['searched below known states', s.descents], ['infeasible (both stages)', s.infeasible],
      ['found on the way', s.found_on_the_way], ['found below known states', s.found_by_descent],
      ['time (s)', fmt(s.stage2_seconds, 3)]
    ];
    var counts = {};
    states.forEach(function (st) {
      var key = st.contacts.length + ' ' + st.dof;
      counts[key] = (counts[key] || 0) + 1;
    });
    var byLayer = Object.keys(counts).map(function (k) {
      var p = k.split(' ');
      return [Number(p[0]), Number(p[1]), counts[k]];
    }).sort(function (a, b) { return a[0] - b[0] || a[1] - b[1]; });
    var total = (s.stage1_seconds || 0) + (s.stage2_seconds || 0);
    function block(title, content) { return el('div', null, [el('h3', { text: title }), content]); }
    box.appendChild(block('Parts', table(parts.slice(1), parts[0])));
    box.appendChild(block('Bounds (options: degenerate states ' + (G.options.degenerate ? 'kept' : 'left out') + ')', table(bounds)));
    box.appendChild(block('Stage 1: primitive contacts', table(stage1)));
    var stage2Block = block('Stage 2: growing states', table(stage2));
    stage2Block.appendChild(el('p', { class: 'note', text: 'A pair gives one outcome per case of the mapping rules, so the counts add up to more than the pairs.' }));
    box.appendChild(stage2Block);
    box.appendChild(block('Graph: ' + s.states + ' states, ' + s.edges + ' edges, ' + fmt(total, 3) + ' s in all',
      table(byLayer.map(function (r) { return [r[0], r[1], r[2]]; }), ['contacts', 'DOF', 'states'])));
  })();

  // ---------- graph ----------
  var cy = null;
  var selected = -1;
  function legend() {
    var box = document.getElementById('legend');
    box.textContent = '';
    if (colourBy === 'dof') {
      box.appendChild(document.createTextNode('DOF:'));
      for (var d = 6; d >= 0; d--) {
        box.appendChild(el('span', null, [el('span', { class: 'swatch', style: 'background:' + seq((6 - d) / 6) }), String(d)]));
      }
    } else {
      box.appendChild(document.createTextNode('contacts:'));
      for (var c = 0; c <= maxContacts; c++) {
        box.appendChild(el('span', null, [el('span', { class: 'swatch', style: 'background:' + seq(maxContacts ? c / maxContacts : 0) }), String(c)]));
      }
    }
    box.appendChild(el('span', { text: '· selected state: red ring; its neighbours: blue edges' }));
  }
  (function buildGraph() {
    var scale = 46;
    var elements = [];
    states.forEach(function (s, i) {
      var p = D.layout[i] || [0, 0];
      elements.push({
        group: 'nodes',
        data: { id: 's' + i, label: String(i), colour: stateColour(s) },
        position: { x: p[0] * scale, y: p[1] * scale }
      });
    });
    G.edges.forEach(function (e, k) {
      elements.push({ group: 'edges', data: { id: 'e' + k, source: 's' + e[0], target: 's' + e[1] } });
    });
    cy = cytoscape({
      container: document.getElementById('cy'),
      elements: elements,
      layout: { name: 'preset', fit: true, padding: 20 },
      minZoom: 0.02,
      maxZoom: 6,
      wheelSensitivity: 0.3,
      boxSelectionEnabled: false,
      autoungrabify: true,
      textureOnViewport: LARGE,
      hideEdgesOnViewport: LARGE,
      pixelRatio: LARGE ? 1 : 'auto',
      style: [
        { selector: 'node', style: {
          'width': 40, 'height': 40, 'background-color': 'data(colour)', 'border-width': 1, 'border-color': '#556',
          'label': 'data(label)', 'font-size': 17, 'text-valign': 'center', 'text-halign': 'center',
          'color': '#111', 'text-outline-color': '#fff', 'text-outline-width': 2, 'min-zoomed-font-size': 5
        } },
        { selector: 'edge', style: { 'width': 1.2, 'line-color': '#9aa3b2', 'curve-style': 'haystack', 'opacity': 0.8 } },
        { selector: 'node.sel', style: { 'border-width': 5, 'border-color': '#e03131', 'z-index': 10 } },
        { selector: 'edge.near', style: { 'line-color': '#1c7ed6', 'width': 3, 'opacity': 1, 'z-index': 9 } },
        { selector: 'node.match', style: { 'border-width': 3, 'border-color': '#1c7ed6' } }
      ]
    });
    cy.on('tap', 'node', function (evt) { select(Number(evt.target.id().slice(1)), false); });
    legend();
  })();
  // Labels must be readable at the first view: when fitting the whole graph would
  // shrink them below 10 px, the first view zooms in (around the selected state, once
  // chosen) and the user zooms out for the whole.
  var LABEL_FONT = 17, LABEL_MIN_PX = 10;
  function readableZoom() { return LABEL_MIN_PX / LABEL_FONT; }
  document.getElementById('colour-by').addEventListener('change', function (e) {
    colourBy = e.target.value;
    cy.batch(function () {
      cy.nodes().forEach(function (n) { n.data('colour', stateColour(states[Number(n.id().slice(1))])); });
    });
    legend();
  });

  // ---------- 3D view ----------
  var view = { ok: false, drawnPixels: 0, size: [0, 0] };
  (function build3d() {
    var box = document.getElementById('view3d');
    var renderer;
    try {
      renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    } catch (err) {
      box.appendChild(el('div', { class: 'note', text: 'The 3D view needs WebGL, which this browser does not offer (' + err.message + ').' }));
      return;
    }
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    renderer.setClearColor(0xeef1f6, 1);
    box.appendChild(renderer.domElement);
    var note = el('div', { class: 'note' });
    box.appendChild(note);
    var scene = new THREE.Scene();
    scene.add(new THREE.HemisphereLight(0xffffff, 0x8090a0, 0.75));
    var sun = new THREE.DirectionalLight(0xffffff, 0.55);
    sun.position.set(1, -2, 3);
    scene.add(sun);
    var camera = new THREE.PerspectiveCamera(35, 1, 0.01, 1e6);
    camera.up.set(0, 0, 1);
    var controls = new THREE.OrbitControls(camera, renderer.domElement);
    controls.enableDamping = false;

    // L: the larger bounding-box diagonal; sizes of highlights scale with it.
    function diag(P) {
      var lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
      P.vertices.forEach(function (v) { for (var k = 0; k < 3; k++) { lo[k] = Math.min(lo[k], v[k]); hi[k] = Math.max(hi[k], v[k]); } });
      return P.vertices.length ? Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) : 1;
    }
    var L = Math.max(diag(G.fixed), diag(G.moving), 1e-9);

    function buildPart(P, colour, opacity) {
      var group = new THREE.Group();
      group.matrixAutoUpdate = false;
      var faceMeshes = [];
      var V = P.vertices;
      P.faces.forEach(function (loops, f) {
        var n = new THREE.Vector3().fromArray(P.face_normals[f]);
        var u = Math.abs(n.x) < 0.9 ? new THREE.Vector3(1, 0, 0) : new THREE.Vector3(0, 1, 0);
        u.cross(n).normalize();
        var w = new THREE.Vector3().crossVectors(n, u);
        var positions = [], flat = [];
        var projected = loops.map(function (loop) {
          return loop.map(function (vi) {
            var p = new THREE.Vector3().fromArray(V[vi]);
            positions.push(p.x, p.y, p.z);
            return new THREE.Vector2(p.dot(u), p.dot(w));
          });
        });
        var triangles = THREE.ShapeUtils.triangulateShape(projected[0], projected.slice(1));
        triangles.forEach(function (t) { flat.push(t[0], t[1], t[2]); });
        var geometry = new THREE.BufferGeometry();
        geometry.setAttribute('position', new THREE.Float32BufferAttribute(positions, 3));
        var normals = [];
        for (var k = 0; k < positions.length / 3; k++) normals.push(n.x, n.y, n.z);
        geometry.setAttribute('normal', new THREE.Float32BufferAttribute(normals, 3));
        geometry.setIndex(flat);
        var material = new THREE.MeshLambertMaterial({
          color: colour, side: THREE.DoubleSide, transparent: opacity < 1, opacity: opacity, depthWrite: opacity >= 1,
          // Touching faces are coplanar: the translucent moving part is pulled towards
          // the viewer and the fixed part pushed away, so neither flickers through.
          polygonOffset: true, polygonOffsetFactor: opacity < 1 ? -1 : 1, polygonOffsetUnits: opacity < 1 ? -2 : 2
        });
        var mesh = new THREE.Mesh(geometry, material);
        group.add(mesh);
        faceMeshes.push(mesh);
      });
      var lines = [];
      P.edges.forEach(function (e) { lines.push.apply(lines, V[e[0]]); lines.push.apply(lines, V[e[1]]); });
      var edgeGeometry = new THREE.BufferGeometry();
      edgeGeometry.setAttribute('position', new THREE.Float32BufferAttribute(lines, 3));
      group.add(new THREE.LineSegments(edgeGeometry, new THREE.LineBasicMaterial({ color: 0x2b3040 })));
      var marks = new THREE.Group();
      group.add(marks);
      scene.add(group);
      return { P: P, group: group, faces: faceMeshes, marks: marks, colour: new THREE.Color(colour) };
    }
    var A = buildPart(G.fixed, 0x9fb3c8, 1);
    var B_OPACITY = 0.55;
    var B = buildPart(G.moving, 0xf2a65a, B_OPACITY);
    var A_OPACITY = 1;
    // Axes of the fixed part's frame at its origin (x red, y green, z blue), a quarter
    // of L long, and their key with the unit of lengths.
    var axes = new THREE.AxesHelper(L * 0.25);
    // Drawn over the parts, so that the axes show even inside a solid's corner.
    axes.material.depthTest = false;
    axes.material.transparent = true;
    axes.renderOrder = 5;
    scene.add(axes);
    box.appendChild(el('div', { class: 'axes' }, [
      'axes at the fixed part\'s origin: ', el('b', { text: 'x', style: 'color:#e03131' }), ' ',
      el('b', { text: 'y', style: 'color:#2f9e44' }), ' ', el('b', { text: 'z', style: 'color:#1c7ed6' }),
      ' · lengths in ' + lengthUnit + ' · axes ' + fmt(L * 0.25, 1) + ' long'
    ]));
    // The name of the face under the mouse.
    var tip = el('div', { class: 'tip' });
    box.appendChild(tip);
    var raycaster = new THREE.Raycaster();
    function labelAt(x, y) {
      var w = box.clientWidth, h = box.clientHeight;
      if (!w || !h) return '';
      raycaster.setFromCamera(new THREE.Vector2(x / w * 2 - 1, -(y / h) * 2 + 1), camera);
      var candidates = [];
      [[A, 'fixed'], [B, 'moving']].forEach(function (pair) {
        if (!pair[0].group.visible) return;
        pair[0].faces.forEach(function (m, f) { m.userData.label = pair[1] + ' part: face f' + f; candidates.push(m); });
      });
      scene.updateMatrixWorld(true);
      var hit = raycaster.intersectObjects(candidates, false)[0];
      if (!hit) return '';
      var label = hit.object.userData.label;
      // The nearest vertex of that part, when the pointer is close to one.
      var part = label.indexOf('fixed') === 0 ? A : B;
      var local = part.group.worldToLocal(hit.point.clone());
      var best = -1, bestD = Infinity;
      part.P.vertices.forEach(function (v, k) {
        var d = local.distanceTo(new THREE.Vector3().fromArray(v));
        if (d < bestD) { bestD = d; best = k; }
      });
      if (best >= 0 && bestD < L * 0.02) label += ', near vertex v' + best;
      return label;
    }
    view.labelAt = labelAt;
    renderer.domElement.addEventListener('mousemove', function (e) {
      var r = renderer.domElement.getBoundingClientRect();
      var text = labelAt(e.clientX - r.left, e.clientY - r.top);
      tip.textContent = text;
      tip.style.display = text ? 'block' : 'none';
      tip.style.left = (e.clientX - r.left + 12) + 'px';
      tip.style.top = (e.clientY - r.top + 12) + 'px';
    });
    renderer.domElement.addEventListener('mouseleave', function () { tip.style.display = 'none'; });
    // See-through: the fixed part translucent, so contacts inside a hole show.
    view.seeThrough = function (on) {
      A_OPACITY = on ? 0.28 : 1;
      A.faces.forEach(function (m) {
        m.material.opacity = A_OPACITY;
        m.material.transparent = A_OPACITY < 1;
        m.material.depthWrite = A_OPACITY >= 1;
        m.material.needsUpdate = true;
      });
      render();
    };
    document.getElementById('see-through').addEventListener('change', function (e) { view.seeThrough(e.target.checked); });
    function setMatrix(obj, m) {
      obj.matrix.set(m[0][0], m[0][1], m[0][2], m[0][3], m[1][0], m[1][1], m[1][2], m[1][3],
        m[2][0], m[2][1], m[2][2], m[2][3], m[3][0], m[3][1], m[3][2], m[3][3]);
      obj.matrixWorldNeedsUpdate = true;
    }
    setMatrix(A.group, [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]);

    var sphere = new THREE.SphereGeometry(1, 20, 14);
    var cylinder = new THREE.CylinderGeometry(1, 1, 1, 12);
    function mark(part, id, colour) {
      var kind = id[0], index = Number(id.slice(1));
      // Marks are drawn over everything, so a touching edge or vertex is never hidden.
      var material = new THREE.MeshLambertMaterial({ color: colour, depthTest: false, transparent: true, opacity: 0.95 });
      var V = part.P.vertices;
      if (kind === 'f') {
        var mesh = part.faces[index];
        if (mesh) { mesh.material.color.set(colour); mesh.material.opacity = Math.max(mesh.material.opacity, 0.9); }
      } else if (kind === 'e') {
        var e = part.P.edges[index];
        if (!e) return;
        var a = new THREE.Vector3().fromArray(V[e[0]]), b = new THREE.Vector3().fromArray(V[e[1]]);
        var c = new THREE.Mesh(cylinder, material);
        var r = L * 0.007;
        c.scale.set(r, a.distanceTo(b), r);
        c.position.copy(a).add(b).multiplyScalar(0.5);
        c.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), b.clone().sub(a).normalize());
        c.renderOrder = 10;
        part.marks.add(c);
      } else if (kind === 'v') {
        if (!V[index]) return;
        var s = new THREE.Mesh(sphere, material);
        s.scale.setScalar(L * 0.018);
        s.position.fromArray(V[index]);
        s.renderOrder = 11;
        part.marks.add(s);
      }
    }
    function clearMarks(part, opacity) {
      part.faces.forEach(function (m) {
        m.material.color.copy(part.colour);
        m.material.opacity = opacity;
      });
      while (part.marks.children.length) {
        var c = part.marks.children.pop();
        c.material.dispose();
      }
    }

    function render() { renderer.render(scene, camera); }
    controls.addEventListener('change', render);
    function resize() {
      var w = box.clientWidth, h = box.clientHeight;
      if (!w || !h) return;
      renderer.setSize(w, h);
      camera.aspect = w / h;
      camera.updateProjectionMatrix();
      render();
    }
    if (window.ResizeObserver) new ResizeObserver(resize).observe(box);
    window.addEventListener('resize', resize);
    var framed = false;
    // The first view looks from the side the fixed part's touching faces face (their
    // outward normals point at the moving part), so the contacts are in sight.
    function firstDirection(s) {
      var d = new THREE.Vector3(1.2, -1.9, 1.1).normalize();
      var n = new THREE.Vector3(), count = 0;
      s.contacts.forEach(function (c) {
        if (c.fixed[0] === 'f' && G.fixed.face_normals[Number(c.fixed.slice(1))]) {
          n.add(new THREE.Vector3().fromArray(G.fixed.face_normals[Number(c.fixed.slice(1))]));
          count++;
        }
      });
      if (count) d.addScaledVector(n.divideScalar(count), 1.5);
      return d.lengthSq() > 1e-6 ? d.normalize() : new THREE.Vector3(1.2, -1.9, 1.1).normalize();
    }
    function frame(s) {
      scene.updateMatrixWorld(true);
      var bb = new THREE.Box3().setFromObject(A.group);
      if (B.group.visible) bb.union(new THREE.Box3().setFromObject(B.group));
      var centre = bb.getCenter(new THREE.Vector3());
      var radius = Math.max(bb.getSize(new THREE.Vector3()).length() / 2, 1e-9);
      var direction = framed ? camera.position.clone().sub(controls.target).normalize() : firstDirection(s);
      var distance = radius / Math.sin(THREE.MathUtils.degToRad(camera.fov / 2)) * 1.05;
      camera.position.copy(centre).addScaledVector(direction, distance);
      camera.near = distance / 1000;
      camera.far = distance * 10;
      camera.updateProjectionMatrix();
      controls.target.copy(centre);
      controls.update();
      framed = true;
    }
    view.show = function (s) {
      clearMarks(A, A_OPACITY);
      clearMarks(B, B_OPACITY);
      if (s.witness) {
        B.group.visible = true;
        setMatrix(B.group, s.witness.matrix);
        note.textContent = '';
      } else {
        B.group.visible = false;
        note.textContent = 'Free space: no witness pose was probed, so only the fixed part is shown.';
      }
      s.contacts.forEach(function (c, k) {
        mark(A, c.fixed, pcColour(k));
        mark(B, c.moving, pcColour(k));
      });
      frame(s);
      resize();
      render();
    };
    view.check = function () {
      render();
      var gl = renderer.getContext();
      var w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
      var pixels = new Uint8Array(w * h * 4);
      gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, pixels);
      var drawn = 0;
      for (var i = 0; i < pixels.length; i += 4) {
        // Anything not the clear colour (238, 241, 246) was drawn.
        if (Math.abs(pixels[i] - 238) + Math.abs(pixels[i + 1] - 241) + Math.abs(pixels[i + 2] - 246) > 12) drawn++;
      }
      view.drawnPixels = drawn;
      view.size = [w, h];
    };
    view.ok = true;
  })();

  // ---------- selection ----------
  var info = document.getElementById('state-info');
  var startedView = false;
  function stateLink(i) {
    var a = el('a', { text: String(i), title: states[i].contacts.map(contactText).join('; ') || 'free space' });
    a.addEventListener('click', function () { select(i, true); });
    return a;
  }
  function select(i, centre) {
    if (!(i >= 0 && i < N)) return;
    selected = i;
    var s = states[i];
    cy.batch(function () {
      cy.elements('.sel, .near').removeClass('sel near');
      var node = cy.getElementById('s' + i);
      node.addClass('sel');
      node.connectedEdges().addClass('near');
    });
    if (centre) cy.animate({ center: { eles: cy.getElementById('s' + i) } }, { duration: 250 });
    if (!startedView) {
      startedView = true;
      if (cy.zoom() < readableZoom()) {
        cy.zoom(readableZoom());
        cy.center(cy.getElementById('s' + i));
      }
    }
    info.textContent = '';
    var title = 'State ' + i + ': ' + (s.contacts.length ? s.contacts.length + ' principal contact' + (s.contacts.length > 1 ? 's' : '') : 'free space') +
      ', ' + s.dof + ' DOF' + (s.degenerate ? ', degenerate' : '');
    info.appendChild(el('div', { class: 'title', text: title }));
    if (s.witness) {
      var p = s.witness.pose;
      info.appendChild(el('div', null, ['witness: ', el('code', {
        text: 'x ' + fmt(p[0]) + ', y ' + fmt(p[1]) + ', z ' + fmt(p[2]) + ', rx ' + fmt(deg(p[3]), 2) + '°, ry ' + fmt(deg(p[4]), 2) + '°, rz ' + fmt(deg(p[5]), 2) + '°'
      })]));
    }
    var list = el('ul');
    s.contacts.forEach(function (c, k) {
      list.appendChild(el('li', null, [
        el('span', { class: 'swatch', style: 'background:' + pcColour(k) }),
        el('code', { text: c.type }), ' fixed ', el('code', { text: c.fixed }), ' × moving ', el('code', { text: c.moving }),
        ' (' + c.dof + ' DOF' + (c.degenerate ? ', degenerate' : '') + ')'
      ]));
    });
    info.appendChild(list);
    var near = el('div', { class: 'neighbours' }, ['neighbours: ']);
    neighbours[i].slice().sort(function (a, b) { return a - b; }).forEach(function (j) { near.appendChild(stateLink(j)); });
    if (!neighbours[i].length) near.appendChild(document.createTextNode('none'));
    info.appendChild(near);
    if (view.ok) view.show(s);
    Array.prototype.forEach.call(document.querySelectorAll('#states tbody tr.selected'), function (r) { r.classList.remove('selected'); });
    var row = document.getElementById('row-' + i);
    if (row) row.classList.add('selected');
    if (history.replaceState) history.replaceState(null, '', '#s' + i);
  }

  // ---------- table ----------
  var ROWS = 300;
  var rowText = states.map(function (s) {
    return ('s' + s.id + ' ' + s.id + ' dof ' + s.dof + ' contacts ' + s.contacts.length + ' ' + (s.degenerate ? 'degenerate ' : '') +
      s.contacts.map(function (c) { return c.type + ' ' + c.fixed + ' ' + c.moving; }).join(' ') +
      (s.contacts.length ? '' : ' free space')).toLowerCase();
  });
  var tbody = document.querySelector('#states tbody');
  function renderTable() {
    var words = document.getElementById('filter').value.toLowerCase().split(/\s+/).filter(Boolean);
    var matches = [];
    for (var i = 0; i < N; i++) {
      var text = rowText[i];
      var ok = words.every(function (w) {
        // A bare number matches a state id exactly, anything else as a substring.
        if (/^\d+$/.test(w)) return (' ' + text + ' ').indexOf(' ' + w + ' ') >= 0;
        return text.indexOf(w) >= 0;
      });
      if (ok) matches.push(i);
    }
    tbody.textContent = '';
    var fragment = document.createDocumentFragment();
    matches.slice(0, ROWS).forEach(function (i) {
      var s = states[i];
      var p = s.witness ? s.witness.pose : null;
      var tr = el('tr', { id: 'row-' + i, class: i === selected ? 'selected' : '' }, [
        el('td', { class: 'n', text: String(i) }),
        el('td', { class: 'n', text: String(s.contacts.length) }),
        el('td', { class: 'n', text: String(s.dof) }),
        el('td', { text: s.degenerate ? 'yes' : '' }),
        el('td', null, [el('code', { text: s.contacts.map(contactText).join('; ') || 'free space' })]),
        el('td', { text: p ? fmt(p[0]) + ', ' + fmt(p[1]) + ', ' + fmt(p[2]) : '' }),
        el('td', { text: p ? fmt(deg(p[3]), 2) + ', ' + fmt(deg(p[4]), 2) + ', ' + fmt(deg(p[5]), 2) : '' })
      ]);
      tr.addEventListener('click', function () { select(i, true); });
      fragment.appendChild(tr);
    });
    tbody.appendChild(fragment);
    document.getElementById('table-count').textContent = matches.length + ' of ' + N + ' states match' +
      (matches.length > ROWS ? ' (first ' + ROWS + ' shown; refine the filter)' : '');
    cy.batch(function () {
      cy.nodes('.match').removeClass('match');
      if (words.length && matches.length < N) {
        matches.forEach(function (i) { cy.getElementById('s' + i).addClass('match'); });
      }
    });
  }
  var pending = null;
  document.getElementById('filter').addEventListener('input', function () {
    clearTimeout(pending);
    pending = setTimeout(renderTable, LARGE ? 150 : 0);
  });
  renderTable();

  // ---------- start ----------
  // The state named in the address (#s12), else the first of the most constrained.
  var first = -1;
  var fromHash = /^#s(\d+)$/.exec(location.hash);
  if (fromHash && Number(fromHash[1]) < N) first = Number(fromHash[1]);
  if (first < 0) {
    states.forEach(function (s, i) {
      if (first < 0 || s.dof < states[first].dof || (s.dof === states[first].dof && s.contacts.length > states[first].contacts.length)) first = i;
    });
  }
  if (first >= 0) select(first, false);
  var setupMs = Math.round(performance.now() - T0);

  // ---------- self check (read by the browser test) ----------
  function selfCheck() {
    var graphPixels = 0;
    Array.prototype.forEach.call(document.querySelectorAll('#cy canvas'), function (c) {
      try {
        var ctx = c.getContext('2d');
        if (!ctx || !c.width || !c.height) return;
        var d = ctx.getImageData(0, 0, c.width, c.height).data;
        for (var i = 3; i < d.length; i += 16) if (d[i] > 0) graphPixels++;
      } catch (err) { /* a canvas of another kind: not counted */ }
    });
    if (view.ok) view.check();
    // Blocks of the summary must not overlap (long paths wrap).
    var blocks = Array.prototype.map.call(document.querySelectorAll('#summary > div'), function (b) { return b.getBoundingClientRect(); });
    var overlaps = 0;
    for (var a = 0; a < blocks.length; a++) {
      for (var b = a + 1; b < blocks.length; b++) {
        var p = blocks[a], q = blocks[b];
        if (p.left < q.right - 1 && q.left < p.right - 1 && p.top < q.bottom - 1 && q.top < p.bottom - 1) overlaps++;
      }
    }
    var wide = Array.prototype.filter.call(document.querySelectorAll('#summary > div'), function (b) { return b.scrollWidth > b.clientWidth + 1; }).length;
    var hover = '';
    var seeThrough = null;
    if (view.ok) {
      var vb = document.getElementById('view3d');
      hover = view.labelAt(vb.clientWidth / 2, vb.clientHeight / 2);
      view.seeThrough(true);
      seeThrough = document.querySelectorAll('#see-through').length === 1;
      view.seeThrough(false);
    }
    document.getElementById('acsg-selftest').textContent = JSON.stringify({
      summary_overlaps: overlaps,
      summary_overflowing: wide,
      label_px: LABEL_FONT * cy.zoom(),
      axes: document.querySelectorAll('#view3d .axes').length === 1,
      axes_text: (document.querySelector('#view3d .axes') || {}).textContent || '',
      hover_centre: hover,
      see_through: seeThrough,
      states: N,
      graph_edges: G.edges.length,
      nodes: cy.nodes().length,
      edges: cy.edges().length,
      graph_pixels: graphPixels,
      webgl: view.ok,
      drawn_pixels: view.drawnPixels,
      canvas: view.size,
      selected: selected,
      table_rows: tbody.children.length,
      setup_ms: setupMs,
      errors: window.acsgErrors
    });
  }
  cy.ready(function () { setTimeout(selfCheck, 400); });
})();
