// mocapseg web worker: loads takes and runs every segmentation method off the page's thread.
// src/protocol.rs defines the messages and src/worker.rs answers them; this file only wires
// postMessage. Every message is {json, buffers}: the request or response as JSON text and its
// bulk data (file bytes, positions, pixels, model files) as transferred buffers.
// Paths are relative to this file: dist/www/worker.js loads dist/pkg/mocapseg.js.
import init, { worker_handle, worker_next } from "../pkg/mocapseg.js";

// The page sends the wasm it compiled as the first message ({wasmModule}); a worker started
// without one (another page) fetches and compiles it itself on its first request. The handler is
// registered synchronously so that no message sent while the wasm is being set up is lost.
let ready = null;
const start = (module) => {
  ready = init(module ? { module_or_path: module } : undefined);
  // the size of this worker's wasm memory, which only grows (make bench reads its peak)
  ready.then((wasm) => { self.__mocapsegMemory = () => wasm.memory.buffer.byteLength; }, () => {});
  ready.catch(() => {}); // reported with the first request instead
};

const post = (message, transfer) => self.postMessage(message, transfer);

// One message (from the page, or one the worker sends itself), then whatever the worker asks to
// do next — the next epoch of a DT-FCN training — after a setTimeout(0): the page's messages that
// arrived meanwhile (a stop) are read first, so a long training never blocks them.
const handle = async (event) => {
  try {
    await ready;
    worker_handle(event.data, post);
    const next = worker_next();
    if (next !== undefined) setTimeout(() => handle({ data: next }), 0);
  } catch (err) {
    // A trap (a bug in the wasm) or a module that failed to load: the module may be broken,
    // so the page replaces this worker ("internal").
    let take = 0;
    let run = null;
    try {
      ({ take = 0, run = null } = JSON.parse(event.data.json));
    } catch {}
    const message = `internal error: ${err?.message ?? err}`;
    post({ json: JSON.stringify({ type: "failed", take, run, message, kind: "internal" }), buffers: [] }, []);
  }
};

self.onmessage = (event) => {
  if (event.data?.wasmModule instanceof WebAssembly.Module) {
    if (!ready) start(event.data.wasmModule);
    return;
  }
  if (!ready) start();
  handle(event);
};
