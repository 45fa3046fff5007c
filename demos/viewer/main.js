// Plays one demo run: run/scene.glb (the animated scene) and run/summary.json (counts and
// frame times per frame). scripts/view.sh serves this folder with the run directory as run/.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

const $ = (id) => document.getElementById(id);
// What the browser test reads: the frame shown and its counts, once the first frame is drawn.
window.viewerState = { ready: false, frame: 0, bodies: null, events: null, error: null };

const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio);
renderer.setSize(window.innerWidth, window.innerHeight);
$('view').appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0xdde2ea);
scene.add(new THREE.HemisphereLight(0xffffff, 0x8a8f99, 1.6));
const sun = new THREE.DirectionalLight(0xffffff, 2.2);
sun.position.set(-0.25, 1.0, 0.55); // the pictures' light: above, left, in front
scene.add(sun);
const camera = new THREE.PerspectiveCamera(35, window.innerWidth / window.innerHeight, 0.01, 1000);
const controls = new OrbitControls(camera, renderer.domElement);

let summary, mixer, bodyNodes = [], eventsPerFrame = [], frameCount = 1, fps = 60, frame = 1, playing = true, last = performance.now();
let loaded = false; // load() finished: the scene, the counts and the body colours are all in place

// The camera the pictures use (azimuth 35°, elevation 24°), framing every body but the ground.
function frameBodies(root) {
  const box = new THREE.Box3();
  root.traverse((o) => { if (o.isMesh && !o.name.startsWith('ground')) box.expandByObject(o); });
  if (box.isEmpty()) box.setFromCenterAndSize(new THREE.Vector3(), new THREE.Vector3(2, 2, 2));
  const centre = box.getCenter(new THREE.Vector3());
  const radius = Math.max(box.getSize(new THREE.Vector3()).length() / 2, 0.1);
  const az = 35 * Math.PI / 180, el = 24 * Math.PI / 180;
  const back = new THREE.Vector3(Math.sin(az) * Math.cos(el), Math.sin(el), Math.cos(az) * Math.cos(el));
  camera.position.copy(centre).addScaledVector(back, radius / Math.sin(17.5 * Math.PI / 180));
  controls.target.copy(centre);
  controls.update();
}

function drawPlot() {
  const canvas = $('plot'), g = canvas.getContext('2d'), ms = summary.ms_per_frame ?? [];
  const w = canvas.width, h = canvas.height, top = Math.max(...ms, 1e-3);
  g.clearRect(0, 0, w, h);
  g.strokeStyle = '#3b6fb6';
  g.beginPath();
  ms.forEach((v, i) => g.lineTo((i / Math.max(ms.length - 1, 1)) * w, h - 12 - (v / top) * (h - 16)));
  g.stroke();
  g.fillStyle = '#c62a1a';
  g.fillRect(((frame - 1) / Math.max(frameCount - 1, 1)) * w - 1, 0, 2, h);
  g.fillStyle = '#21262e';
  g.fillText(`step time, max ${top.toFixed(2)} ms`, 4, h - 2);
}

function show(f) {
  frame = Math.min(Math.max(1, Math.round(f)), frameCount);
  if (mixer) mixer.setTime(frame / fps);
  // Counted from the scene itself: bodies shown (hidden ones have scale 0) and the events
  // scene.glb carries, so that the test can hold them against summary.json.
  const bodies = bodyNodes.filter((n) => n.scale.x > 0).length;
  const events = eventsPerFrame[frame - 1] ?? null;
  const total = eventsPerFrame.slice(0, frame).reduce((a, b) => a + b, 0);
  $('timeline').value = frame;
  $('clock').textContent = `frame ${frame}/${frameCount} · t = ${(frame / fps).toFixed(2)} s`;
  $('bodies').textContent = bodies ?? '–';
  $('events').textContent = events ?? '–';
  $('events-total').textContent = total;
  drawPlot();
  Object.assign(window.viewerState, { frame, bodies, events });
}

function tick(now) {
  if (playing && mixer) {
    const advance = Math.floor(((now - last) / 1000) * fps);
    if (advance > 0) {
      show(frame >= frameCount ? 1 : frame + advance);
      last = now;
    }
  } else {
    last = now;
  }
  controls.update();
  renderer.render(scene, camera);
  if (!window.viewerState.ready && loaded) window.viewerState.ready = true; // a frame of the loaded run has been drawn
  requestAnimationFrame(tick);
}

async function load() {
  const run = new URLSearchParams(location.search).get('run') ?? 'run/';
  summary = await (await fetch(run + 'summary.json')).json();
  frameCount = summary.frames;
  fps = summary.fps;
  $('title').textContent = `shatter-${summary.demo}`;
  $('timeline').max = frameCount;
  const gltf = await new GLTFLoader().loadAsync(run + 'scene.glb');
  scene.add(gltf.scene);
  mixer = new THREE.AnimationMixer(gltf.scene);
  bodyNodes = gltf.scene.children.filter((n) => n.name !== 'ground');
  eventsPerFrame = gltf.scene.userData.events_per_frame ?? [];
  for (const clip of gltf.animations) mixer.clipAction(clip).play();
  frameBodies(gltf.scene);

  $('status').textContent = `${summary.description}  ·  ${frameCount} frames at ${fps} fps`;
  playing = new URLSearchParams(location.search).get('paused') === null;
  $('play').textContent = playing ? 'Pause' : 'Play';
  show(Number(new URLSearchParams(location.search).get('frame') ?? 1));
  // The colours (sRGB) of the bodies shown now, for the browser test to look for in the picture.
  // (Not getWorldScale: three reads a singular matrix's scale as 1.)
  const shown = (o) => !o || (o.scale.x > 0 && shown(o.parent));
  const colours = new Set();
  gltf.scene.traverse((o) => {
    if (o.isMesh && !['ground', 'crack'].includes(o.material.name) && shown(o))
      colours.add('#' + o.material.color.getHexString(THREE.SRGBColorSpace));
  });
  window.viewerState.colours = [...colours];
  loaded = true;
}

$('play').addEventListener('click', () => { playing = !playing; $('play').textContent = playing ? 'Pause' : 'Play'; });
$('timeline').addEventListener('input', (e) => { playing = false; $('play').textContent = 'Play'; show(Number(e.target.value)); });
window.addEventListener('resize', () => {
  camera.aspect = window.innerWidth / window.innerHeight;
  camera.updateProjectionMatrix();
  renderer.setSize(window.innerWidth, window.innerHeight);
});
load().catch((e) => {
  window.viewerState.error = String(e);
  $('status').textContent = `cannot load the run: ${e}`;
});
requestAnimationFrame(tick);
