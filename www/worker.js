// mocapseg web worker: parses a BVH file, runs forward kinematics and builds the motion image,
// and runs the SSSM segmentation (Krüger et al. 2017) on the take it loaded last, all off the
// page's thread (src/worker.rs does the work; this file only wires messages).
//
// Page → worker: {id, name, bytes: ArrayBuffer}            (bytes transferred)
//                {id, kind: "sssm", params: "<JSON>"}
// Worker → page: {type: "progress", id, stage, fraction}
//                {type: "done", id, summary, skeleton, bounds, positions, image}
//                {type: "error", id, message, fatal}
//                {type: "sssm-progress", id, stage, fraction}
//                {type: "sssm-done", id, report, image: {size, block, rgba}}
//                {type: "sssm-error", id, message, fatal}
// Paths are relative to this file: dist/www/worker.js loads dist/pkg/mocapseg.js.
import init, { worker_load, worker_sssm } from "../pkg/mocapseg.js";

// Start loading the module at once, but register the handler synchronously so that no message
// sent while the wasm is still compiling is lost.
const ready = init();
ready.catch(() => {}); // reported to the page with the first load instead

// The wasm entry points throw a string for bad input. Anything else (a wasm trap after a panic,
// a module that failed to load) may have left the module broken: the page starts a new worker.
function failure(type, id, err, what) {
  if (typeof err === "string") return { type, id, message: err, fatal: false };
  return { type, id, message: `${what}: internal error: ${err?.message ?? err}`, fatal: true };
}

async function load({ id, name, bytes }) {
  try {
    await ready;
    const progress = (stage, fraction) => self.postMessage({ type: "progress", id, stage, fraction });
    const result = worker_load(new Uint8Array(bytes), name, progress);
    const transfer = [result.positions.buffer, result.image.rgba.buffer, result.image.png.buffer];
    self.postMessage({ type: "done", id, ...result }, transfer);
  } catch (err) {
    self.postMessage(failure("error", id, err, name));
  }
}

async function sssm({ id, params }) {
  try {
    await ready;
    const progress = (stage, fraction) => self.postMessage({ type: "sssm-progress", id, stage, fraction });
    const result = worker_sssm(params, progress);
    self.postMessage({ type: "sssm-done", id, ...result }, [result.image.rgba.buffer]);
  } catch (err) {
    self.postMessage(failure("sssm-error", id, err, "SSSM"));
  }
}

self.onmessage = (event) => (event.data.kind === "sssm" ? sssm(event.data) : load(event.data));
