// mocapseg web worker: parses a BVH file, runs forward kinematics and builds the motion image
// off the page's thread (src/worker.rs does the work; this file only wires messages).
//
// Page → worker: {id, name, bytes: ArrayBuffer}            (bytes transferred)
// Worker → page: {type: "progress", id, stage, fraction}
//                {type: "done", id, summary, skeleton, bounds, positions, image}
//                {type: "error", id, message, fatal}
// Paths are relative to this file: dist/www/worker.js loads dist/pkg/mocapseg.js.
import init, { worker_load } from "../pkg/mocapseg.js";

// Start loading the module at once, but register the handler synchronously so that no message
// sent while the wasm is still compiling is lost.
const ready = init();
ready.catch(() => {}); // reported to the page with the first load instead

self.onmessage = async (event) => {
  const { id, name, bytes } = event.data;
  try {
    await ready;
    const progress = (stage, fraction) => self.postMessage({ type: "progress", id, stage, fraction });
    const result = worker_load(new Uint8Array(bytes), name, progress);
    const transfer = [result.positions.buffer, result.image.rgba.buffer, result.image.png.buffer];
    self.postMessage({ type: "done", id, ...result }, transfer);
  } catch (err) {
    // worker_load throws a string for bad input. Anything else (a wasm trap after a panic, a
    // module that failed to load) may have left the module broken: the page starts a new worker.
    if (typeof err === "string") {
      self.postMessage({ type: "error", id, message: err, fatal: false });
    } else {
      self.postMessage({ type: "error", id, message: `${name}: internal error: ${err?.message ?? err}`, fatal: true });
    }
  }
};
