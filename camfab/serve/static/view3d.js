// The studio's 3-D view: the cam as camfab writes it (its STL files) and its follower, placed
// at each of the report animation's frames by the scene camfab.serve.scene makes (lengths in
// mm, in the STL files' coordinates; every matrix 16 numbers, row by row).
//
//   const view = new View3D(container);
//   view.setScene(scene, buffers);   // buffers: an ArrayBuffer per part, in scene.parts order
//   view.show(frame);                // the frame's index, as the report's slider counts them
//   view.dispose();
//
// The view draws on demand (a new frame, a move of the camera, a resize), never in a loop. It
// keeps the camera while the scene's files stay the same (the same design, edited) and fits
// it to the first scene and to a new design's. Without WebGL it says so in the container.
// It sets container.dataset.frame to the frame shown and container.dataset.ready to "yes" once
// the first scene is drawn.

import * as THREE from "three";
import { OrbitControls } from "./three/OrbitControls.js";
import { STLLoader } from "./three/STLLoader.js";

const BACKGROUND = 0xf4f5f7;
const CAM_COLOUR = 0xaeb4bd; // a neutral steel grey
const FOLLOWER_COLOUR = 0xd2691e; // a warm orange, distinct from the cam
const AXIS_COLOUR = 0x555555;
// The direction the camera looks from at first: from +X (the follower, on +Y, to the right),
// a little in front and above (Z is up).
const VIEW_FROM = new THREE.Vector3(1.0, -0.35, 0.8).normalize();
const FIELD_OF_VIEW_DEG = 35;
const NO_WEBGL = "3-D view needs WebGL";

/** Whether the browser gives a WebGL 2 context (three.js draws with nothing less). */
function hasWebGL() {
  try {
    const canvas = document.createElement("canvas");
    return !!(window.WebGL2RenderingContext && canvas.getContext("webgl2"));
  } catch (error) {
    return false;
  }
}

/** A three.js matrix of 16 numbers given row by row. */
function matrixOf(numbers) {
  return new THREE.Matrix4().set(...numbers);
}

/** A knife's wedge: its edge along Z through the origin, opening toward +Y. */
function wedgeGeometry(width, height, length) {
  const w = width / 2;
  const z = length / 2;
  const corners = [
    [0, 0, -z], [-w, height, -z], [w, height, -z],
    [0, 0, z], [-w, height, z], [w, height, z],
  ];
  const faces = [
    [0, 2, 1], [3, 4, 5], // the ends
    [0, 1, 4], [0, 4, 3], // the sides
    [0, 3, 5], [0, 5, 2],
    [1, 2, 5], [1, 5, 4], // the back
  ];
  const positions = new Float32Array(faces.length * 9);
  faces.forEach((face, i) => face.forEach((corner, j) => {
    positions.set(corners[corner], i * 9 + j * 3);
  }));
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute("position", new THREE.BufferAttribute(positions, 3));
  geometry.computeVertexNormals();
  return geometry;
}

/** A mushroom's face: the sphere of *radius* within *angle* of its −Y pole, closed flat. */
function capGeometry(radius, angle) {
  const steps = 24;
  const points = [];
  for (let i = 0; i <= steps; i += 1) {
    const a = (angle * i) / steps;
    points.push(new THREE.Vector2(radius * Math.sin(a), -radius * Math.cos(a)));
  }
  points.push(new THREE.Vector2(0, -radius * Math.cos(angle)));
  return new THREE.LatheGeometry(points, 48);
}

/** The geometry of one of the follower's shapes, in the shape's own frame. */
function shapeGeometry(shape) {
  switch (shape.type) {
    case "cylinder": {
      const geometry = new THREE.CylinderGeometry(shape.radius, shape.radius, shape.length, 48);
      geometry.rotateX(Math.PI / 2); // three.js stands it along Y; the scene lays it along Z
      return geometry;
    }
    case "box":
      return new THREE.BoxGeometry(shape.x, shape.y, shape.z);
    case "wedge":
      return wedgeGeometry(shape.width, shape.height, shape.length);
    case "cap":
      return capGeometry(shape.radius, shape.angle);
    default:
      return null;
  }
}

export class View3D {
  /** A view drawn into *container* (its size follows the container's). */
  constructor(container) {
    this.container = container;
    this.scene = null;
    this.frame = 0;
    this.files = null;
    this.renderer = null;
    this.message = null;
    if (!hasWebGL()) {
      this._sayNoWebGL();
      return;
    }
    try {
      this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    } catch (error) {
      this.renderer = null;
      this._sayNoWebGL();
      return;
    }
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.renderer.setClearColor(BACKGROUND);
    this.renderer.domElement.style.display = "block";
    container.appendChild(this.renderer.domElement);

    this.world = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(FIELD_OF_VIEW_DEG, 1, 0.1, 1000);
    this.camera.up.set(0, 0, 1);
    this.world.add(this.camera);
    this.world.add(new THREE.HemisphereLight(0xffffff, 0x8d8d8d, 1.6));
    const key = new THREE.DirectionalLight(0xffffff, 2.2);
    key.position.set(0.5, 1, 1); // with the camera: lit from over the viewer's shoulder
    this.camera.add(key);

    this.camMaterial = new THREE.MeshStandardMaterial({
      color: CAM_COLOUR, metalness: 0.35, roughness: 0.5, side: THREE.DoubleSide,
    });
    this.followerMaterial = new THREE.MeshStandardMaterial({
      color: FOLLOWER_COLOUR, metalness: 0.1, roughness: 0.6, side: THREE.DoubleSide,
    });
    this.parts = [];
    this.content = new THREE.Group(); // the parts and the follower (what the camera fits)
    this.world.add(this.content);
    this.follower = new THREE.Group();
    this.follower.matrixAutoUpdate = false;
    this.content.add(this.follower);
    this.axis = null;

    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this._onChange = () => this.render();
    this.controls.addEventListener("change", this._onChange);
    this._resize();
    this._observer = new ResizeObserver(() => {
      this._resize();
      this.render();
    });
    this._observer.observe(container);
  }

  /**
   * Show *scene* (camfab.serve.scene's JSON) with its parts' STL files (*buffers*, in the
   * order of scene.parts), at the frame shown so far. The camera stays where the user put it
   * when the files are those of the scene before.
   */
  setScene(scene, buffers) {
    const files = scene.parts.map((part) => part.file).join("\n");
    const fit = this.scene === null || files !== this.files;
    this.scene = scene;
    this.files = files;
    if (this.renderer !== null) {
      this._clear();
      const loader = new STLLoader();
      scene.parts.forEach((part, i) => {
        const buffer = buffers ? buffers[i] : undefined;
        if (!buffer) { // a part whose file did not come: shown without it
          this.parts.push(null);
          return;
        }
        const mesh = new THREE.Mesh(loader.parse(buffer), this.camMaterial);
        mesh.matrixAutoUpdate = false;
        this.parts.push(mesh);
        this.content.add(mesh);
      });
      for (const shape of scene.follower.shapes) {
        const geometry = shapeGeometry(shape);
        if (geometry === null) continue;
        const mesh = new THREE.Mesh(geometry, this.followerMaterial);
        mesh.matrixAutoUpdate = false;
        mesh.matrix.copy(matrixOf(shape.matrix));
        this.follower.add(mesh);
      }
      this._addAxis(scene);
    }
    this.show(Math.min(this.frame, scene.frames - 1));
    if (fit && this.renderer !== null) {
      this._fit();
      this.render();
    }
    this.container.dataset.ready = "yes";
  }

  /** Move the cam and the follower to *frame* (an index of the scene's frames) and draw. */
  show(frame) {
    if (this.scene === null) return;
    const count = this.scene.frames;
    const index = Math.max(0, Math.min(count - 1, Math.round(Number(frame)) || 0));
    this.frame = index;
    if (this.renderer !== null) {
      this.scene.parts.forEach((part, i) => {
        const mesh = this.parts[i];
        if (!mesh) return;
        mesh.matrix.copy(matrixOf(part.matrices[index]));
        mesh.matrixWorldNeedsUpdate = true;
      });
      this.follower.matrix.copy(matrixOf(this.scene.follower.matrices[index]));
      this.follower.matrixWorldNeedsUpdate = true;
      this.render();
    }
    this.container.dataset.frame = String(index);
  }

  /** Draw the view as it stands. */
  render() {
    if (this.renderer !== null) this.renderer.render(this.world, this.camera);
  }

  /** Let go of everything the view made, and take it out of the container. */
  dispose() {
    if (this.renderer !== null) {
      this._observer.disconnect();
      this.controls.removeEventListener("change", this._onChange);
      this.controls.dispose();
      this._clear();
      this.camMaterial.dispose();
      this.followerMaterial.dispose();
      this.renderer.dispose();
      this.renderer.domElement.remove();
      this.renderer = null;
    } else if (this.message !== null) {
      this.message.remove();
      this.message = null;
    }
    this.scene = null;
  }

  _sayNoWebGL() {
    this.message = document.createElement("p");
    this.message.className = "no-webgl";
    this.message.textContent = NO_WEBGL;
    this.container.appendChild(this.message);
  }

  _clear() {
    for (const mesh of this.parts) {
      if (!mesh) continue;
      this.content.remove(mesh);
      mesh.geometry.dispose();
    }
    this.parts = [];
    for (const mesh of [...this.follower.children]) {
      this.follower.remove(mesh);
      mesh.geometry.dispose();
    }
    if (this.axis !== null) {
      this.world.remove(this.axis);
      this.axis.geometry.dispose();
      this.axis.material.dispose();
      this.axis = null;
    }
  }

  /** The axis the cam turns about (or slides along), across the scene's bounds. */
  _addAxis(scene) {
    const point = new THREE.Vector3(...scene.axis.point);
    const direction = new THREE.Vector3(...scene.axis.direction).normalize();
    const low = new THREE.Vector3(...scene.bounds.min);
    const high = new THREE.Vector3(...scene.bounds.max);
    const reach = 0.6 * high.distanceTo(low);
    const ends = [point.clone().addScaledVector(direction, -reach),
      point.clone().addScaledVector(direction, reach)];
    const geometry = new THREE.BufferGeometry().setFromPoints(ends);
    const material = new THREE.LineDashedMaterial({
      color: AXIS_COLOUR, dashSize: reach / 20, gapSize: reach / 40,
    });
    this.axis = new THREE.Line(geometry, material);
    this.axis.computeLineDistances();
    this.world.add(this.axis);
  }

  /** Aim the camera at the middle of the parts and the follower as they stand, from far
   * enough to see them whole as the cam turns. */
  _fit() {
    this.content.updateMatrixWorld(true);
    const box = new THREE.Box3().setFromObject(this.content);
    if (box.isEmpty()) {
      box.set(new THREE.Vector3(...this.scene.bounds.min),
        new THREE.Vector3(...this.scene.bounds.max));
    }
    const sphere = box.getBoundingSphere(new THREE.Sphere());
    const centre = sphere.center;
    const radius = Math.max(sphere.radius, 1e-3);
    const half = THREE.MathUtils.degToRad(FIELD_OF_VIEW_DEG / 2);
    const fit = Math.min(1, this.camera.aspect || 1);
    const distance = radius / Math.sin(half * fit);
    this.camera.position.copy(centre).addScaledVector(VIEW_FROM, distance);
    this.camera.near = distance / 100;
    this.camera.far = distance * 100;
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(centre);
    this.controls.update();
  }

  _resize() {
    const width = Math.max(1, this.container.clientWidth);
    const height = Math.max(1, this.container.clientHeight);
    this.renderer.setSize(width, height);
    this.camera.aspect = width / height;
    this.camera.updateProjectionMatrix();
  }
}
