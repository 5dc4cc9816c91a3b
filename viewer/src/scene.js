// The three.js scene of a recording: one mesh per body with its real shape, posed per frame and
// coloured by part; the constraint-graph overlay; a ground grid; an orbit camera with z up.
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { LineSegments2 } from 'three/examples/jsm/lines/LineSegments2.js';
import { LineSegmentsGeometry } from 'three/examples/jsm/lines/LineSegmentsGeometry.js';
import { LineMaterial } from 'three/examples/jsm/lines/LineMaterial.js';
import { PALETTE } from './colouring.js';
import { isInterface } from './recording.js';

const STATIC_COLOUR = 0x8c8c8c;

// Geometry in the body's shape frame; three's capsule and cylinder axes are y, rbpart's z.
function bodyGeometry(body) {
  switch (body.shape) {
    case 'sphere': return new THREE.SphereGeometry(body.radius, 24, 16);
    case 'box': {
      const h = body.halfExtents;
      return new THREE.BoxGeometry(2 * h[0], 2 * h[1], 2 * h[2]);
    }
    case 'capsule': return new THREE.CapsuleGeometry(body.radius, 2 * body.halfLength, 8, 20).rotateX(Math.PI / 2);
    case 'cylinder':
      return new THREE.CylinderGeometry(body.radius, body.radius, 2 * body.halfLength, 24).rotateX(Math.PI / 2);
    case 'convex': {
      // Fan triangulation of each (convex, counter-clockwise) hull face; unindexed, so each
      // face gets its own flat normal.
      const pos = [];
      const v = body.vertices, off = body.faceOffsets, idx = body.faceIndices;
      for (let f = 0; f + 1 < off.length; ++f)
        for (let k = off[f] + 1; k + 1 < off[f + 1]; ++k)
          for (const i of [idx[off[f]], idx[k], idx[k + 1]]) pos.push(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
      g.computeVertexNormals();
      return g;
    }
  }
  throw new Error(`unknown shape ${body.shape}`);
}

// A cache key for shapes that are the same whatever the body (chain links, logs, boxes).
function shapeKey(body) {
  switch (body.shape) {
    case 'sphere': return `s${body.radius}`;
    case 'box': return `b${body.halfExtents.join(',')}`;
    case 'capsule':
    case 'cylinder': return `${body.shape}${body.radius},${body.halfLength}`;
    default: return null;
  }
}

function setPose(object, p, offset = 0) {
  object.position.set(p[offset], p[offset + 1], p[offset + 2]);
  object.quaternion.set(p[offset + 4], p[offset + 5], p[offset + 6], p[offset + 3]); // stored w x y z
}

// The three-quarter view from the front right and above that the viewer opens with (degrees).
export const DEFAULT_CAMERA = { azimuth: -55, elevation: 25 };

// Unit vector from the target to the camera: `azimuth` counter-clockwise from +x about z (0: the
// camera on the +x side, 90: on the +y side), `elevation` above the xy plane. A view straight
// down or up is tilted by 0.01 degrees, as the camera's up vector is z.
export function cameraDirection(azimuth, elevation) {
  const a = THREE.MathUtils.degToRad(azimuth);
  const e = THREE.MathUtils.degToRad(Math.max(-89.99, Math.min(89.99, elevation)));
  return new THREE.Vector3(Math.cos(e) * Math.cos(a), Math.cos(e) * Math.sin(a), Math.sin(e));
}

export class SceneView {
  // `flat`: unlit colours (exact palette pixels; for figures and the viewer's own test).
  // `camera`: fitCamera's options (azimuth, elevation, zoom), applied when the view is first sized.
  constructor(canvas, recording, { flat = false, camera = {} } = {}) {
    this.recording = recording;
    this.cameraOptions = camera;
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: !flat, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0xf4f5f7);
    this.camera = new THREE.PerspectiveCamera(40, 1, 0.01, 1000);
    this.camera.up.set(0, 0, 1);
    this.controls = new OrbitControls(this.camera, canvas);
    this.controls.addEventListener('change', () => this.render());

    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x8a8f99, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.6);
    sun.position.set(3, -5, 8);
    this.scene.add(sun);

    const Material = flat ? THREE.MeshBasicMaterial : THREE.MeshLambertMaterial;
    this.partMaterials = PALETTE.map((c) => new Material({ color: c, transparent: true }));
    this.staticMaterial = new Material({ color: STATIC_COLOUR, transparent: true, opacity: 0.25, depthWrite: false });

    const geometries = new Map();
    this.meshes = recording.bodies.map((body) => {
      const key = shapeKey(body);
      let g = key && geometries.get(key);
      if (!g) {
        g = bodyGeometry(body);
        if (key) geometries.set(key, g);
      }
      const mesh = new THREE.Mesh(g, body.isStatic ? this.staticMaterial : this.partMaterials[0]);
      setPose(mesh, body.pose);
      this.scene.add(mesh);
      return mesh;
    });

    this.addGraphOverlay();
    this.addGrid();
  }

  // Nodes at the bodies' centres of mass, edges inside parts thin, interface edges bold; drawn
  // over the bodies (no depth test), which turn translucent while the overlay is shown.
  addGraphOverlay() {
    const n = this.recording.bodyOf.length;
    this.nodeMesh = new THREE.InstancedMesh(
      new THREE.SphereGeometry(1, 10, 8),
      new THREE.MeshBasicMaterial({ depthTest: false, transparent: true }),
      Math.max(n, 1));
    this.nodeMesh.count = n;
    this.nodeMesh.renderOrder = 3;
    this.innerEdges = new THREE.LineSegments(
      new THREE.BufferGeometry(),
      new THREE.LineBasicMaterial({ color: 0x303030, depthTest: false, transparent: true, opacity: 0.8 }));
    this.innerEdges.renderOrder = 1;
    this.interfaceMaterial = new LineMaterial({ color: 0x111111, linewidth: 4, depthTest: false, transparent: true });
    this.interfaceEdges = new LineSegments2(new LineSegmentsGeometry(), this.interfaceMaterial);
    this.interfaceEdges.renderOrder = 2;
    this.graph = new THREE.Group();
    this.graph.add(this.innerEdges, this.interfaceEdges, this.nodeMesh);
    this.graph.visible = false;
    this.scene.add(this.graph);
    // The overlay's geometry changes every frame: no culling rather than new bounds each time.
    for (const o of this.graph.children) o.frustumCulled = false;
    // Node size: a quarter of the median dynamic body's bounding radius.
    const radii = this.recording.bodyOf.map((b) => {
      const g = this.meshes[b].geometry;
      if (!g.boundingSphere) g.computeBoundingSphere();
      return g.boundingSphere.radius;
    }).sort((a, b) => a - b);
    this.nodeRadius = 0.25 * (radii.length ? radii[radii.length >> 1] : 0.1);
  }

  // Ground grid on z = 0 (three's grid lies in its xz plane), sized to the scene at the start.
  addGrid() {
    const box = new THREE.Box3();
    for (const mesh of this.meshes) box.expandByObject(mesh);
    if (box.isEmpty()) box.set(new THREE.Vector3(-1, -1, 0), new THREE.Vector3(1, 1, 1));
    const centre = box.getCenter(new THREE.Vector3());
    const size = Math.max(2, Math.ceil(2 * Math.max(box.max.x - box.min.x, box.max.y - box.min.y)));
    const grid = new THREE.GridHelper(size, size * 2, 0x9aa0aa, 0xd0d4da);
    grid.rotateX(Math.PI / 2);
    grid.position.set(Math.round(centre.x), Math.round(centre.y), 0);
    this.scene.add(grid);
  }

  // The camera on the dynamic bodies as they are now (the first frame shown), with the static ones
  // still drawn: a floor slab much larger than the bodies would otherwise shrink them to a line.
  // `azimuth` (degrees counter-clockwise from +x, about z) and `elevation` (above the horizon) give
  // the direction from the bodies to the camera; the camera moves along it until the bounding box's
  // corners fill 90% of the view (the bounding sphere alone would leave the bodies small), repeated
  // because projection is not linear; `zoom` then divides that distance.
  fitCamera({ azimuth = DEFAULT_CAMERA.azimuth, elevation = DEFAULT_CAMERA.elevation, zoom = 1 } = {}) {
    const dynamic = new THREE.Box3(), all = new THREE.Box3();
    this.recording.bodies.forEach((body, i) => {
      if (!body.isStatic) dynamic.expandByObject(this.meshes[i]);
      if (this.meshes[i].visible) all.expandByObject(this.meshes[i]);
    });
    const box = dynamic.isEmpty() ? all.clone() : dynamic;
    if (box.isEmpty()) box.set(new THREE.Vector3(-1, -1, 0), new THREE.Vector3(1, 1, 1));
    const centre = box.getCenter(new THREE.Vector3());
    const diagonal = Math.max(box.getSize(new THREE.Vector3()).length(), 0.1);
    const direction = cameraDirection(azimuth, elevation);
    const corners = [];
    for (let i = 0; i < 8; ++i)
      corners.push(new THREE.Vector3(i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y,
        i & 4 ? box.max.z : box.min.z));
    this.controls.target.copy(centre);
    this.camera.near = diagonal / 200;
    this.camera.far = diagonal * 50;
    this.camera.updateProjectionMatrix();
    let distance = diagonal / Math.sin(THREE.MathUtils.degToRad(this.camera.fov / 2));
    for (let iteration = 0; iteration < 4; ++iteration) {
      this.camera.position.copy(centre).addScaledVector(direction, distance);
      this.camera.lookAt(centre);
      this.camera.updateMatrixWorld();
      let extent = 0;
      for (const c of corners) {
        const p = c.clone().project(this.camera);
        extent = Math.max(extent, Math.abs(p.x), Math.abs(p.y));
      }
      distance *= extent / 0.9; // projected size ~ 1/distance
    }
    // Seen along a long body (a chain end-on), its near end alone would fill the view: the camera
    // stays outside the box's bounding sphere.
    distance = Math.max(distance, 0.6 * diagonal) / zoom;
    this.camera.position.copy(centre).addScaledVector(direction, distance);
    // The static bodies stay in view as far as they reach behind the dynamic ones.
    const reach = all.isEmpty() ? 0 : all.getSize(new THREE.Vector3()).length();
    this.camera.near = Math.min(diagonal / 200, distance / 10);
    this.camera.far = Math.max(diagonal * 50, distance + reach);
    this.camera.updateProjectionMatrix();
    this.controls.update();
  }

  resize(width, height) {
    this.renderer.setSize(width, height, false);
    this.camera.aspect = width / Math.max(height, 1);
    this.camera.updateProjectionMatrix();
    if (!this.fitted) this.fitCamera(this.cameraOptions);
    this.fitted = true;
    this.interfaceMaterial.resolution.set(width, height);
    this.render();
  }

  setStaticVisible(visible) {
    this.recording.bodies.forEach((body, i) => {
      if (body.isStatic) this.meshes[i].visible = visible;
    });
  }

  // Poses, part colours and overlay of frame `f` in channel `channel` with `colours` (per part).
  show(f, channel, colours, showGraph) {
    const rec = this.recording;
    const frame = rec.frames[f];
    const c = frame.channels[channel];
    const poses = frame.poses;
    rec.bodyOf.forEach((body, node) => {
      const mesh = this.meshes[body];
      setPose(mesh, poses, 7 * node);
      mesh.material = this.partMaterials[colours[c.partOf[node]]];
    });
    for (const m of this.partMaterials) m.opacity = showGraph ? 0.35 : 1;
    for (const m of this.partMaterials) m.depthWrite = !showGraph;
    this.graph.visible = showGraph;
    if (showGraph) this.updateGraph(frame, c, colours);
    this.render();
  }

  updateGraph(frame, c, colours) {
    const rec = this.recording;
    const n = rec.bodyOf.length;
    const r = this.nodeRadius;
    const centres = new Float32Array(3 * n);
    const m = new THREE.Matrix4(), q = new THREE.Quaternion(), p = new THREE.Vector3(), s = new THREE.Vector3(r, r, r);
    const colour = new THREE.Color();
    for (let v = 0; v < n; ++v) {
      const mesh = this.meshes[rec.bodyOf[v]];
      p.fromArray(rec.bodies[rec.bodyOf[v]].com).applyQuaternion(mesh.quaternion).add(mesh.position);
      p.toArray(centres, 3 * v);
      m.compose(p, q, s);
      this.nodeMesh.setMatrixAt(v, m);
      this.nodeMesh.setColorAt(v, colour.setHex(PALETTE[colours[c.partOf[v]]]));
    }
    this.nodeMesh.instanceMatrix.needsUpdate = true;
    if (this.nodeMesh.instanceColor) this.nodeMesh.instanceColor.needsUpdate = true;
    const inner = [], outer = [];
    for (let e = 0; e < frame.edgeU.length; ++e) {
      const list = isInterface(c, e) ? outer : inner;
      const a = 3 * frame.edgeU[e], b = 3 * frame.edgeV[e];
      list.push(centres[a], centres[a + 1], centres[a + 2], centres[b], centres[b + 1], centres[b + 2]);
    }
    this.innerEdges.geometry.setAttribute('position', new THREE.Float32BufferAttribute(inner, 3));
    // LineSegmentsGeometry keeps its buffer size from the first call: a new one per frame.
    this.interfaceEdges.geometry.dispose();
    this.interfaceEdges.geometry = new LineSegmentsGeometry().setPositions(outer.length ? outer : [0, 0, 0, 0, 0, 0]);
    this.interfaceEdges.visible = outer.length > 0;
  }

  render() {
    this.renderer.render(this.scene, this.camera);
  }
}
