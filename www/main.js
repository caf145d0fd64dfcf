// mocapseg page entry: starts the wasm app. A file of its own (not an inline <script>) so that the
// page's Content-Security-Policy (index.html) can allow scripts from the page's origin only.
// Paths are relative to this file: dist/www/main.js loads dist/pkg/mocapseg.js.
import init, { mount_app } from "../pkg/mocapseg.js";

try {
  await init();
  mount_app();
} catch (err) {
  document.body.dataset.state = "error";
  const root = document.getElementById("mocapseg-app");
  root.textContent = "mocapseg could not start: " + err;
  throw err;
}
