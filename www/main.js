// mocapseg page entry: starts the wasm app. A file of its own (not an inline <script>) so that the
// page's Content-Security-Policy (index.html) can allow scripts from the page's origin only.
// Paths are relative to this file: dist/www/main.js loads dist/pkg/mocapseg.js.
import init, { mount_app } from "../pkg/mocapseg.js";

// The service worker (dist/sw.js, docs/page.md "Offline"): the app works offline after this visit.
// Only where the browser offers service workers (not on file://, not in some private modes); the
// page works the same without one.
function registerServiceWorker() {
  if (!("serviceWorker" in navigator) || !window.isSecureContext) return;
  let updating = false;
  // a new build installed while this page runs an older one: offer to switch (never by itself:
  // the page would change version under the user's hands)
  const offer = (worker) => {
    if (!navigator.serviceWorker.controller || document.getElementById("sw-update")) return;
    const bar = document.createElement("div");
    bar.id = "sw-update";
    bar.className = "ms-sw-update";
    bar.setAttribute("role", "status");
    bar.append("A new version of mocapseg is ready. ");
    const button = document.createElement("button");
    button.id = "sw-update-reload";
    button.type = "button";
    button.textContent = "Reload to update";
    button.addEventListener("click", () => {
      updating = true;
      worker.postMessage({ type: "skip-waiting" });
    });
    bar.append(button);
    document.body.append(bar);
  };
  navigator.serviceWorker.addEventListener("controllerchange", () => {
    if (updating) location.reload();
  });
  navigator.serviceWorker
    .register(new URL("../sw.js", import.meta.url), { scope: new URL("../", import.meta.url).pathname })
    .then((registration) => {
      if (registration.waiting) offer(registration.waiting);
      registration.addEventListener("updatefound", () => {
        const worker = registration.installing;
        worker?.addEventListener("statechange", () => {
          if (worker.state === "installed") offer(worker);
        });
      });
    })
    .catch((err) => console.info(`mocapseg works without offline use here: ${err?.message ?? err}`));
}

// The wasm is compiled once, here, and the same compiled module goes to the page's web worker
// (src/app/loader: `globalThis.__mocapsegWasm`, posted as the worker's first message), which would
// otherwise fetch and compile its 6 MB again while the page waits for its first result.
async function compileWasm() {
  const url = new URL("../pkg/mocapseg_bg.wasm", import.meta.url);
  try {
    return await WebAssembly.compileStreaming(fetch(url));
  } catch {
    // a server that does not send application/wasm: compile from the bytes
    const response = await fetch(url);
    if (!response.ok) throw new Error(`${url}: HTTP ${response.status}`);
    return WebAssembly.compile(await response.arrayBuffer());
  }
}

try {
  const module = await compileWasm();
  performance.mark("mocapseg:wasm-compiled"); // make bench-page reports when (tests/e2e/page-load.bench.mjs)
  globalThis.__mocapsegWasm = module;
  await init({ module_or_path: module });
  mount_app();
  performance.mark("mocapseg:mounted");
} catch (err) {
  document.body.dataset.state = "error";
  const root = document.getElementById("mocapseg-app");
  root.textContent = "mocapseg could not start: " + err;
  throw err;
}
// Registered once the page shows its first result (or after 10 s): the service worker then
// precaches every file of the build, the models included (docs/page.md "Offline"), and that
// download and its checks must not slow the first visit's own loading.
const METHOD_DONE = /^(done|error)$/;
const shown = () => Object.entries(document.body.dataset).some(([k, v]) => k !== "state" && METHOD_DONE.test(v))
  || document.body.dataset.state === "error";
if (shown()) {
  registerServiceWorker();
} else {
  let registered = false;
  const once = () => {
    if (registered) return;
    registered = true;
    observer.disconnect();
    registerServiceWorker();
  };
  const observer = new MutationObserver(() => { if (shown()) once(); });
  observer.observe(document.body, { attributes: true });
  setTimeout(once, 10_000);
}
