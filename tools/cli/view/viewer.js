// The hedra view page's script: reads the model from the JSON block
// #hedra-data (view_html.cpp writes it), builds the side panel, then the
// three.js scene, renders once and sets window.hedraViewReady.
//
// Frames: the model is in world coordinates (doubles). Everything drawn is
// translated by the centre of the model's bounding box before it becomes
// float32 vertex data, so a scene at 1e6 draws as crisply as one at the
// origin; the panel prints the original world coordinates.
//
// Scenes: every body is a translucent polygon mesh with its edges (a rounded
// body's core is drawn as lighter edges inside); every query draws its
// witness points (A red, B blue), the segment between them, the normal as an
// arrow from A, and its contact points (orange: penetrating, teal:
// speculative). Continuous queries: a cast's or toi's moving bodies are drawn
// at their start and end (ghosted edges, dashed at the end) and solid at the
// query's fraction; a raycast's ray is a line from its origin to its last
// point with the hit point (A red) and the surface normal there. Clicking a
// query in the panel shows only that query and highlights its pair; clicking
// it again shows all.
// Hulls: input points (grey), hull vertices (dark), faces, edges; clicking a
// face (or typing its number) lists its half-edges and draws them as arrows.
// Rendering is on demand (after a camera move, a selection or a resize).
(function () {
  'use strict';

  const data = JSON.parse(document.getElementById('hedra-data').textContent);
  const viewport = document.getElementById('hedra-viewport');
  const labelLayer = document.getElementById('hedra-labels');
  const panel = document.getElementById('hedra-panel');
  const root = document.documentElement;

  // ---- small helpers --------------------------------------------------------
  function el(tag, className, text) {
    const e = document.createElement(tag);
    if (className) e.className = className;
    if (text !== undefined && text !== null) e.textContent = text;
    return e;
  }
  function num(x) {
    if (x === null || x === undefined) return 'n/a';
    if (!Number.isFinite(x)) return String(x);
    if (x === 0) return '0';
    const a = Math.abs(x);
    return a >= 1e-4 && a < 1e7 ? String(parseFloat(x.toPrecision(7))) : x.toExponential(4);
  }
  function fmt(x) {
    if (x === null || x === undefined) return 'n/a';
    if (typeof x === 'boolean') return x ? 'yes' : 'no';
    if (Array.isArray(x)) return '(' + x.map(num).join(', ') + ')';
    if (typeof x === 'number') return num(x);
    return String(x);
  }
  function finitePoint(p) {
    return Array.isArray(p) && p.length === 3 && p.every(Number.isFinite);
  }
  function row(table, label, value, className) {
    const tr = el('tr');
    tr.appendChild(el('th', null, label));
    tr.appendChild(el('td', className || null, value));
    table.appendChild(tr);
    return tr;
  }

  const palette = [0x4e79a7, 0xf28e2b, 0x59a14f, 0xb07aa1, 0x76b7b2, 0xedc948, 0xff9da7, 0x9c755f, 0xe15759, 0xbab0ac];
  const colorA = 0xd62728, colorB = 0x1f5fbf, colorNormal = 0x2ca02c;
  const colorPenetrating = 0xff7f0e, colorSpeculative = 0x17becf, colorHalfEdge = 0x7b2fbf;

  const bodies = data.bodies || [];
  const queries = data.queries || [];
  const hull = data.hull || null;
  const bodyIndex = new Map();
  bodies.forEach((b, i) => bodyIndex.set(b.name, i));

  // ---- bounds and the drawing frame ----------------------------------------
  const bounds = new THREE.Box3();
  function grow(p) {
    if (finitePoint(p)) bounds.expandByPoint(new THREE.Vector3(p[0], p[1], p[2]));
  }
  bodies.forEach((b) => b.mesh.vertices.forEach(grow));
  queries.forEach((q) => {
    grow(q.point_a);
    grow(q.point_b);
    (q.contacts || []).forEach((c) => grow(c.point));
    (q.sweeps || []).forEach((s) => [s.start, s.end, s.at_fraction].forEach((m) => m.vertices.forEach(grow)));
    if (q.ray) {
      grow(q.ray.origin);
      grow(q.ray.end);
    }
  });
  if (hull) {
    hull.vertices.forEach(grow);
    hull.input_points.forEach(grow);
  }
  const center = bounds.isEmpty() ? new THREE.Vector3() : bounds.getCenter(new THREE.Vector3());
  let radius = bounds.isEmpty() ? 1 : 0.5 * bounds.getSize(new THREE.Vector3()).length();
  if (!(radius > 0)) radius = Math.max(1e-3 * center.length(), 1);
  function local(p) {
    return new THREE.Vector3(p[0] - center.x, p[1] - center.y, p[2] - center.z);
  }
  const marker = radius * 0.018;

  // ---- the side panel -------------------------------------------------------
  panel.appendChild(el('h1', null, data.title || 'hedra view'));
  panel.appendChild(
    el('div', 'help', 'Drag: orbit · right-drag or shift-drag: pan · wheel: zoom · ' +
      (hull ? 'click a face to list its half-edges.' : 'click a query to show only it and highlight its pair.')));
  if (data.description) panel.appendChild(el('p', 'description', data.description));
  (data.notes || []).forEach((n) => panel.appendChild(el('div', 'note', n)));

  const queryItems = [];
  if (bodies.length > 0) {
    panel.appendChild(el('h2', null, 'Bodies (' + bodies.length + ')'));
    bodies.forEach((b, i) => {
      const item = el('div', 'hedra-item');
      const swatch = el('span', 'hedra-swatch');
      swatch.style.background = '#' + palette[i % palette.length].toString(16).padStart(6, '0');
      item.appendChild(swatch);
      item.appendChild(el('b', null, b.name));
      item.appendChild(document.createTextNode(' ' + b.shape + (b.margin > 0 ? ', margin ' + num(b.margin) : '') +
        ' · ' + b.mesh.vertices.length + ' vertices, ' + b.mesh.faces.length + ' faces'));
      item.style.cursor = 'default';
      panel.appendChild(item);
    });
  }
  if (queries.length > 0) {
    panel.appendChild(el('h2', null, 'Queries (' + queries.length + ')'));
    const legend = el('div', 'help hedra-legend');
    [['A', colorA], ['B', colorB], ['normal', colorNormal], ['penetrating', colorPenetrating],
      ['speculative', colorSpeculative]].forEach(([label, color]) => {
      const span = el('span');
      const swatch = el('span', 'hedra-swatch');
      swatch.style.background = '#' + color.toString(16).padStart(6, '0');
      span.appendChild(swatch);
      span.appendChild(document.createTextNode(label));
      legend.appendChild(span);
    });
    panel.appendChild(legend);
    queries.forEach((q, i) => {
      const item = el('div', 'hedra-item');
      item.setAttribute('data-query', String(i));
      const ok = q.status === 'ok';
      item.appendChild(el('span', 'hedra-status ' + (ok ? 'ok' : 'bad'), q.status || 'n/a'));
      item.appendChild(el('b', null, '#' + i + ' ' + (q.ray ? 'ray – ' + q.a : q.a + ' – ' + q.b)));
      item.appendChild(document.createTextNode(' ' + q.type));
      const table = el('table');
      if (q.ray || q.type === 'cast' || q.type === 'toi') {
        row(table, 'hit', fmt(q.hit));
        row(table, 'fraction', fmt(q.fraction));
        if (q.ray) {
          row(table, 'origin', fmt(q.ray.origin), 'mono');
          row(table, 'hit point', fmt(q.ray.hit_point), 'mono');
          row(table, 'normal', fmt(q.normal), 'mono');
        } else {
          row(table, 'initially overlapping', fmt(q.initially_overlapping));
          row(table, 'distance', fmt(q.distance));
          row(table, 'point A', fmt(q.point_a), 'mono');
          row(table, 'point B', fmt(q.point_b), 'mono');
          row(table, 'normal', fmt(q.normal), 'mono');
          row(table, 'moving', (q.sweeps || []).map((s) => s.body).join(', ') || 'none');
        }
        item.appendChild(table);
        item.addEventListener('click', () => selectQuery(i));
        panel.appendChild(item);
        queryItems.push(item);
        return;
      }
      row(table, 'intersecting', fmt(q.intersecting));
      row(table, 'distance', fmt(q.distance));
      row(table, 'point A', fmt(q.point_a), 'mono');
      row(table, 'point B', fmt(q.point_b), 'mono');
      row(table, 'normal', fmt(q.normal), 'mono');
      const contacts = q.contacts || [];
      row(table, 'contacts', String(contacts.length));
      contacts.forEach((c, k) => row(table, '  ' + (k + 1), fmt(c.point) + ' depth ' + num(c.depth), 'mono'));
      item.appendChild(table);
      item.addEventListener('click', () => selectQuery(i));
      panel.appendChild(item);
      queryItems.push(item);
    });
  }

  let faceSection = null;
  if (hull) {
    panel.appendChild(el('h2', null, 'Hull'));
    const table = el('table');
    const v = hull.vertices.length, e = hull.edge_count, f = hull.faces.length;
    row(table, 'input', hull.input);
    row(table, 'input points', String(hull.input_count));
    row(table, 'vertices', String(v));
    row(table, 'edges', String(e));
    row(table, 'faces', String(f));
    row(table, 'V − E + F', String(v - e + f));
    row(table, 'dimension', String(hull.dimension));
    row(table, 'volume', num(hull.volume));
    row(table, 'area', num(hull.area));
    row(table, 'max outside distance', num(hull.max_outside_distance));
    panel.appendChild(table);
    const legend = el('div', 'help', 'grey dots: input points · dark dots: hull vertices');
    panel.appendChild(legend);
    panel.appendChild(el('h2', null, 'Face'));
    const chooser = el('div');
    chooser.appendChild(document.createTextNode('face number '));
    const input = el('input');
    input.type = 'number';
    input.min = '0';
    input.max = String(Math.max(f - 1, 0));
    input.style.width = '6em';
    input.addEventListener('change', () => {
      const k = parseInt(input.value, 10);
      if (k >= 0 && k < f) {
        lookAtFace(k);
        selectFace(k);
      }
    });
    chooser.appendChild(input);
    panel.appendChild(chooser);
    faceSection = el('div', 'help', f > 0 ? 'Click a face, or type its number.' : 'This hull has no faces.');
    panel.appendChild(faceSection);
  }

  // ---- three.js scene -------------------------------------------------------
  const renderer = new THREE.WebGLRenderer({antialias: true, preserveDrawingBuffer: true});
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  viewport.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xf3f4f6);
  const camera = new THREE.PerspectiveCamera(40, 1, radius * 1e-3, radius * 1e3);
  camera.up.set(0, 0, 1);  // shapes' axes are local z; draw world z up
  // Far enough for the bounding sphere to fit the narrower field of view.
  {
    const aspect = Math.max(viewport.clientWidth, 1) / Math.max(viewport.clientHeight, 1);
    const halfFov = camera.fov / 2 * Math.PI / 180;
    const half = Math.min(halfFov, Math.atan(Math.tan(halfFov) * aspect));
    camera.position.set(1.45, -2.05, 1.1).normalize().multiplyScalar(1.05 * radius / Math.sin(half));
  }
  scene.add(camera);
  scene.add(new THREE.AmbientLight(0xffffff, 0.55));
  const light = new THREE.DirectionalLight(0xffffff, 0.6);
  light.position.set(0.4, 0.8, 1.0);
  camera.add(light);  // lit from the viewer, whatever the orbit
  const controls = new THREE.OrbitControls(camera, renderer.domElement);
  controls.screenSpacePanning = true;
  controls.target.set(0, 0, 0);
  controls.update();

  function fanTriangles(points, faces, out, perTriangle) {
    faces.forEach((face, f) => {
      for (let k = 1; k + 1 < face.length; ++k) {
        [face[0], face[k], face[k + 1]].forEach((i) => out.push(points[i].x, points[i].y, points[i].z));
        if (perTriangle) perTriangle(f);
      }
    });
  }
  function triangleGeometry(positions) {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(positions, 3));
    g.computeVertexNormals();
    return g;
  }
  function segmentGeometry(points, edges) {
    const positions = [];
    edges.forEach(([i, j]) => positions.push(points[i].x, points[i].y, points[i].z, points[j].x, points[j].y,
      points[j].z));
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(positions, 3));
    return g;
  }
  function pointGeometry(points) {
    const positions = [];
    points.forEach((p) => positions.push(p.x, p.y, p.z));
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(positions, 3));
    return g;
  }
  function darker(color, factor) {
    return new THREE.Color(color).multiplyScalar(factor);
  }

  // Labels: HTML elements kept over 3D points, placed in render().
  let labels = [];
  function clearLabels() {
    labels.forEach((l) => l.element.remove());
    labels = [];
  }
  function addLabel(text, position, className) {
    const element = el('div', 'hedra-label' + (className ? ' ' + className : ''), text);
    labelLayer.appendChild(element);
    labels.push({element: element, position: position.clone()});
  }

  // Bodies.
  const bodyViews = bodies.map((b, i) => {
    const color = palette[i % palette.length];
    const points = b.mesh.vertices.map(local);
    const group = new THREE.Group();
    const view = {group: group, faceMaterial: null, edgeMaterial: null, coreMaterial: null, centroid: new THREE.Vector3()};
    points.forEach((p) => view.centroid.add(p));
    if (points.length > 0) view.centroid.multiplyScalar(1 / points.length);
    if (b.mesh.faces.length > 0) {
      const positions = [];
      fanTriangles(points, b.mesh.faces, positions);
      view.faceMaterial = new THREE.MeshPhongMaterial({
        color: color, transparent: true, opacity: 0.32, side: THREE.DoubleSide, depthWrite: false,
        flatShading: true, polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1});
      group.add(new THREE.Mesh(triangleGeometry(positions), view.faceMaterial));
    } else {
      group.add(new THREE.Points(pointGeometry(points), new THREE.PointsMaterial({color: color, size: 7,
        sizeAttenuation: false})));
    }
    // Curved surfaces have many polygons: their edges are drawn fainter.
    view.edgeOpacity = b.mesh.faces.length > 100 ? 0.35 : 1;
    view.edgeMaterial = new THREE.LineBasicMaterial({color: darker(color, 0.6), transparent: true,
      opacity: view.edgeOpacity});
    group.add(new THREE.LineSegments(segmentGeometry(points, b.mesh.edges), view.edgeMaterial));
    if (b.core && b.core.edges) {
      const corePoints = b.core.vertices.map(local);
      view.coreMaterial = new THREE.LineBasicMaterial({color: color, transparent: true, opacity: 0.7});
      group.add(new THREE.LineSegments(segmentGeometry(corePoints, b.core.edges), view.coreMaterial));
    }
    scene.add(group);
    view.color = color;
    return view;
  });

  // Queries.
  const sphereGeometry = new THREE.SphereBufferGeometry(marker, 16, 12);
  const contactGeometry = new THREE.OctahedronBufferGeometry(marker * 0.9);
  let sweepPoses = 0, rays = 0;
  // A moving body's pose: solid faces at the fraction, ghosted edges (dashed
  // at the end) at the start and the end.
  function addSweep(group, s) {
    const color = palette[(bodyIndex.has(s.body) ? bodyIndex.get(s.body) : 0) % palette.length];
    [['start', 0.3, false], ['end', 0.3, true], ['at_fraction', 1, false]].forEach(([key, opacity, dashed]) => {
      const m = s[key];
      const points = m.vertices.map(local);
      const material = dashed
        ? new THREE.LineDashedMaterial({color: darker(color, 0.6), transparent: true, opacity: opacity,
          dashSize: marker, gapSize: marker})
        : new THREE.LineBasicMaterial({color: darker(color, key === 'at_fraction' ? 0.45 : 0.6), transparent: true,
          opacity: opacity});
      const lines = new THREE.LineSegments(segmentGeometry(points, m.edges), material);
      if (dashed) lines.computeLineDistances();
      group.add(lines);
      if (key === 'at_fraction' && m.faces.length > 0) {
        const positions = [];
        fanTriangles(points, m.faces, positions);
        group.add(new THREE.Mesh(triangleGeometry(positions), new THREE.MeshPhongMaterial({
          color: color, transparent: true, opacity: 0.7, side: THREE.DoubleSide, flatShading: true,
          polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1})));
      }
      ++sweepPoses;
    });
  }
  const queryViews = queries.map((q) => {
    const group = new THREE.Group();
    const view = {group: group, a: null, b: null, contacts: []};
    (q.sweeps || []).forEach((s) => addSweep(group, s));
    if (q.ray && finitePoint(q.ray.origin) && finitePoint(q.ray.end)) {
      const g = new THREE.BufferGeometry().setFromPoints([local(q.ray.origin), local(q.ray.end)]);
      group.add(new THREE.Line(g, new THREE.LineBasicMaterial({color: 0x111111})));
      const o = new THREE.Mesh(sphereGeometry, new THREE.MeshBasicMaterial({color: 0x111111}));
      o.position.copy(local(q.ray.origin));
      group.add(o);
      if (finitePoint(q.ray.hit_point)) {
        view.a = local(q.ray.hit_point);
        const m = new THREE.Mesh(sphereGeometry, new THREE.MeshBasicMaterial({color: colorA}));
        m.position.copy(view.a);
        group.add(m);
      }
      ++rays;
    }
    if (finitePoint(q.point_a)) {
      view.a = local(q.point_a);
      const m = new THREE.Mesh(sphereGeometry, new THREE.MeshBasicMaterial({color: colorA}));
      m.position.copy(view.a);
      group.add(m);
    }
    if (finitePoint(q.point_b)) {
      view.b = local(q.point_b);
      const m = new THREE.Mesh(sphereGeometry, new THREE.MeshBasicMaterial({color: colorB}));
      m.position.copy(view.b);
      group.add(m);
    }
    if (view.a && view.b) {
      const g = new THREE.BufferGeometry().setFromPoints([view.a, view.b]);
      group.add(new THREE.Line(g, new THREE.LineBasicMaterial({color: 0x111111})));
    }
    (q.contacts || []).forEach((c) => {
      if (!finitePoint(c.point)) return;
      const p = local(c.point);
      const m = new THREE.Mesh(contactGeometry,
        new THREE.MeshBasicMaterial({color: c.depth > 0 ? colorPenetrating : colorSpeculative}));
      m.position.copy(p);
      group.add(m);
      view.contacts.push({position: p, depth: c.depth});
    });
    if (finitePoint(q.normal)) {
      const n = new THREE.Vector3(q.normal[0], q.normal[1], q.normal[2]);
      let origin = view.a;
      if (!origin && view.contacts.length > 0) {
        origin = new THREE.Vector3();
        view.contacts.forEach((c) => origin.add(c.position));
        origin.multiplyScalar(1 / view.contacts.length);
      }
      if (origin && n.lengthSq() > 0) {
        const length = radius * 0.3;
        group.add(new THREE.ArrowHelper(n.normalize(), origin, length, colorNormal, length * 0.25, length * 0.12));
      }
    }
    scene.add(group);
    return view;
  });

  // Hull.
  let hullPoints = null, faceMesh = null, triangleFace = [];
  const faceHighlight = new THREE.Group();
  if (hull) {
    hullPoints = hull.vertices.map(local);
    const inputPoints = hull.input_points.map(local);
    scene.add(new THREE.Points(pointGeometry(inputPoints),
      new THREE.PointsMaterial({color: 0x8a93a3, size: 3, sizeAttenuation: false})));
    scene.add(new THREE.Points(pointGeometry(hullPoints),
      new THREE.PointsMaterial({color: 0x1d2430, size: 6, sizeAttenuation: false})));
    if (hull.faces.length > 0) {
      const positions = [], colors = [];
      fanTriangles(hullPoints, hull.faces, positions, (f) => triangleFace.push(f));
      // Neighbouring faces differ in shade, so merged polygons read as one face.
      triangleFace.forEach((f) => {
        const c = new THREE.Color().setHSL(0.58 + 0.06 * Math.sin(f * 2.4), 0.45, 0.55 + 0.12 * Math.sin(f * 1.7));
        for (let k = 0; k < 3; ++k) colors.push(c.r, c.g, c.b);
      });
      const g = triangleGeometry(positions);
      g.setAttribute('color', new THREE.Float32BufferAttribute(colors, 3));
      faceMesh = new THREE.Mesh(g, new THREE.MeshPhongMaterial({
        vertexColors: THREE.VertexColors, transparent: true, opacity: 0.5, side: THREE.DoubleSide,
        depthWrite: false, flatShading: true, polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1}));
      scene.add(faceMesh);
    }
    const edges = [];
    hull.half_edges.forEach((h, e) => {
      if (e < h[1]) edges.push([h[0], hull.half_edges[h[1]][0]]);
    });
    if (edges.length === 0 && hullPoints.length === 2) edges.push([0, 1]);
    scene.add(new THREE.LineSegments(segmentGeometry(hullPoints, edges),
      new THREE.LineBasicMaterial({color: 0x1d2430})));
    scene.add(faceHighlight);
  }

  const axes = new THREE.AxesHelper(radius * 0.25);
  axes.position.copy(local([0, 0, 0]));
  scene.add(axes);

  // ---- rendering ------------------------------------------------------------
  function render() {
    renderer.render(scene, camera);
    const w = viewport.clientWidth, h = viewport.clientHeight;
    const v = new THREE.Vector3();
    labels.forEach((l) => {
      v.copy(l.position).project(camera);
      const visible = v.z > -1 && v.z < 1;
      l.element.style.display = visible ? '' : 'none';
      l.element.style.left = ((v.x + 1) / 2 * w).toFixed(1) + 'px';
      l.element.style.top = ((1 - v.y) / 2 * h).toFixed(1) + 'px';
    });
  }
  function resize() {
    const w = Math.max(viewport.clientWidth, 1), h = Math.max(viewport.clientHeight, 1);
    renderer.setSize(w, h);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    render();
  }
  controls.addEventListener('change', render);
  window.addEventListener('resize', resize);

  function setHash(hash) {
    try {
      history.replaceState(null, '', hash || window.location.pathname + window.location.search);
    } catch (e) {
      // Some browsers refuse replaceState on file:// pages; the selection still works.
    }
  }

  // ---- selection: queries ---------------------------------------------------
  let selectedQuery = -1;
  function applyQuerySelection() {
    const q = selectedQuery >= 0 ? queries[selectedQuery] : null;
    bodyViews.forEach((view, i) => {
      const involved = !q || bodies[i].name === q.a || bodies[i].name === q.b;
      if (view.faceMaterial) view.faceMaterial.opacity = !q ? 0.32 : involved ? 0.45 : 0.05;
      view.edgeMaterial.opacity = involved ? view.edgeOpacity : 0.1;
      if (view.coreMaterial) view.coreMaterial.opacity = involved ? 0.7 : 0.1;
    });
    queryViews.forEach((view, i) => {
      view.group.visible = !q || i === selectedQuery;
    });
    queryItems.forEach((item, i) => item.classList.toggle('selected', i === selectedQuery));
    if (q) queryItems[selectedQuery].scrollIntoView({block: 'nearest'});
    clearLabels();
    bodyViews.forEach((view, i) => {
      if (!q || bodies[i].name === q.a || bodies[i].name === q.b) addLabel(bodies[i].name, view.centroid, 'body');
    });
    if (q) {
      const view = queryViews[selectedQuery];
      if (view.a) addLabel('A', view.a);
      if (view.b) addLabel('B', view.b);
      view.contacts.forEach((c) => addLabel('depth ' + num(c.depth), c.position));
    }
    root.setAttribute('data-hedra-selected-query', String(selectedQuery));
  }
  function selectQuery(i) {
    selectedQuery = i === selectedQuery ? -1 : i;
    applyQuerySelection();
    setHash(selectedQuery >= 0 ? '#query=' + selectedQuery : '');
    render();
  }

  // ---- selection: hull faces ------------------------------------------------
  // Turns the camera around the target to look at face f's outside (used
  // when a face is chosen by number, not by a click on it).
  function lookAtFace(f) {
    const face = hull.faces[f];
    const c = new THREE.Vector3(), n = new THREE.Vector3();
    face.forEach((i) => c.add(hullPoints[i]));
    c.multiplyScalar(1 / face.length);
    face.forEach((i, k) => {
      const p = hullPoints[i], q = hullPoints[face[(k + 1) % face.length]];
      n.add(p.clone().sub(c).cross(q.clone().sub(c)));
    });
    if (!(n.lengthSq() > 0)) return;
    const distance = camera.position.distanceTo(controls.target);
    camera.position.copy(c).addScaledVector(n.normalize(), distance);
    controls.target.copy(c);
    controls.update();
  }
  function selectFace(f) {
    while (faceHighlight.children.length > 0) faceHighlight.remove(faceHighlight.children[0]);
    clearLabels();
    faceSection.textContent = '';
    root.setAttribute('data-hedra-selected-face', String(f));
    setHash('#face=' + f);
    const face = hull.faces[f];
    const halfEdges = hull.face_half_edges[f];
    const c = new THREE.Vector3();
    face.forEach((i) => c.add(hullPoints[i]));
    c.multiplyScalar(1 / face.length);
    // Newell's normal of the polygon (world orientation is unchanged by the shift).
    const n = new THREE.Vector3();
    face.forEach((i, k) => {
      const p = hullPoints[i], q = hullPoints[face[(k + 1) % face.length]];
      n.x += (p.y - q.y) * (p.z + q.z);
      n.y += (p.z - q.z) * (p.x + q.x);
      n.z += (p.x - q.x) * (p.y + q.y);
    });
    n.normalize();
    const positions = [];
    fanTriangles(hullPoints, [face], positions);
    faceHighlight.add(new THREE.Mesh(triangleGeometry(positions), new THREE.MeshBasicMaterial({
      color: 0xffc14d, transparent: true, opacity: 0.75, side: THREE.DoubleSide, depthWrite: false})));
    const lift = n.clone().multiplyScalar(radius * 0.004);
    halfEdges.forEach((e) => {
      const h = hull.half_edges[e];
      const from = hullPoints[h[0]], to = hullPoints[hull.half_edges[h[2]][0]];
      // Shrunk toward the face's centre, so the twin (in the next face) stays apart.
      const a = c.clone().lerp(from, 0.85).add(lift), b = c.clone().lerp(to, 0.85).add(lift);
      const span = b.clone().sub(a);
      const start = a.clone().addScaledVector(span, 0.08);
      const length = span.length() * 0.84;
      if (!(length > 0)) return;
      const head = Math.min(length * 0.35, radius * 0.08);
      faceHighlight.add(new THREE.ArrowHelper(span.normalize(), start, length, colorHalfEdge, head, head * 0.5));
      addLabel('e' + e, a.clone().lerp(b, 0.5));
    });
    faceSection.appendChild(el('div', null, 'face ' + f + ': ' + face.length + ' half-edges, normal ' +
      fmt([n.x, n.y, n.z])));
    const table = el('table', 'mono');
    table.setAttribute('id', 'hedra-half-edges');
    const header = el('tr');
    ['half-edge', 'origin → dest', 'twin', 'next', 'twin face'].forEach((t) => header.appendChild(el('th', null, t)));
    table.appendChild(header);
    halfEdges.forEach((e) => {
      const h = hull.half_edges[e];
      const twin = hull.half_edges[h[1]];
      const tr = el('tr');
      tr.setAttribute('data-half-edge', String(e));
      tr.appendChild(el('td', null, String(e)));
      tr.appendChild(el('td', null, h[0] + ' → ' + hull.half_edges[h[2]][0]));
      tr.appendChild(el('td', null, String(h[1])));
      tr.appendChild(el('td', null, String(h[2])));
      const neighbour = el('td', 'hedra-link', String(twin[3]));
      neighbour.addEventListener('click', () => selectFace(twin[3]));
      tr.appendChild(neighbour);
      table.appendChild(tr);
    });
    faceSection.appendChild(table);
    render();
  }

  // A click (not a drag) on the viewport picks a hull face.
  let down = null;
  renderer.domElement.addEventListener('pointerdown', (e) => {
    down = {x: e.clientX, y: e.clientY};
  });
  renderer.domElement.addEventListener('pointerup', (e) => {
    if (!down || Math.hypot(e.clientX - down.x, e.clientY - down.y) > 4 || !faceMesh) return;
    const rect = renderer.domElement.getBoundingClientRect();
    const mouse = new THREE.Vector2((e.clientX - rect.left) / rect.width * 2 - 1,
      -((e.clientY - rect.top) / rect.height) * 2 + 1);
    const raycaster = new THREE.Raycaster();
    raycaster.setFromCamera(mouse, camera);
    const hits = raycaster.intersectObject(faceMesh);
    if (hits.length > 0 && hits[0].faceIndex !== undefined) selectFace(triangleFace[hits[0].faceIndex]);
  });

  // ---- first render ---------------------------------------------------------
  root.setAttribute('data-hedra-bodies', String(bodyViews.length));
  root.setAttribute('data-hedra-queries', String(queryViews.length));
  root.setAttribute('data-hedra-sweep-poses', String(sweepPoses));
  root.setAttribute('data-hedra-rays', String(rays));
  root.setAttribute('data-hedra-hull-faces', String(hull ? hull.faces.length : 0));
  applyQuerySelection();
  const hash = window.location.hash;
  const queryMatch = /^#query=(\d+)$/.exec(hash), faceMatch = /^#face=(\d+)$/.exec(hash);
  if (queryMatch && +queryMatch[1] < queries.length) selectQuery(+queryMatch[1]);
  if (faceMatch && hull && +faceMatch[1] < hull.faces.length) {
    lookAtFace(+faceMatch[1]);
    selectFace(+faceMatch[1]);
  }
  resize();
  window.hedraViewReady = true;
  root.setAttribute('data-hedra-ready', 'true');
})();
