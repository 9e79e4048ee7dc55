// memloop view: the page. Plain JavaScript, no library: every view is a function of the address
// (#/loops, #/loop/N, #/matrix, #/graph, #/session/S, #/location/ID, #/edits) that reads the server's JSON
// API and writes the page. Edits send the token memloop view printed (X-Memloop-Token).
"use strict";

const PAGE = 50;        // loop closures per page
const IMAGES_PAGE = 120;
let summary = null;
let chosen = [];        // images picked for a loop closure to add
const token = (() => {
  const match = location.hash.match(/token=([0-9a-f]+)/);
  if (match) {
    sessionStorage.setItem("memloop-token", match[1]);
    history.replaceState(null, "", location.pathname + "#/");
  }
  return sessionStorage.getItem("memloop-token") || "";
})();

function esc(text) {
  return String(text).replace(/[&<>"']/g, c => ({"&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;", "'": "&#39;"}[c]));
}

async function api(path, options) {
  const response = await fetch(path, options);
  const body = await response.json();
  if (!response.ok) throw new Error(body.error || response.statusText);
  return body;
}

function canEdit() { return token && summary && !summary.read_only; }

async function edit(body) {
  try {
    const done = await api("/api/edits", {
      method: "POST", headers: {"Content-Type": "application/json", "X-Memloop-Token": token},
      body: JSON.stringify(body)});
    await loadSummary();
    show(`Edit ${done.id} (${esc(done.action)}) kept in the map.`);
  } catch (error) {
    show(`<span class="error">Refused: ${esc(error.message)}</span>`);
    return;
  }
  route();
}

function show(html) {
  const banner = document.getElementById("banner");
  banner.innerHTML = html;
  banner.hidden = !html;
}

function imageLabel(index, name) { return name ? `${esc(name)} <span class="muted">#${index}</span>` : `#${index}`; }

// A loop closure's match: another robot's image (a fleet's map) has no picture here.
function matchLabel(loop) {
  return loop.match_robot ? `robot ${esc(loop.match_robot)} #${loop.match_image}` : imageLabel(loop.match_image, loop.match_name);
}
function matchThumb(loop) { return loop.match_robot ? "" : thumb(loop.match_image, loop.match_name); }

function thumb(index, name) {
  return summary.images_folder
    ? `<img class="thumb" loading="lazy" src="/api/thumbnails/${index}" alt="${esc(name || index)}">`
    : "";
}

function loopButtons(loop) {
  if (!canEdit()) return "";
  if (loop.state === "rejected" || loop.state === "added") {
    return `<button data-undo="${loop.edit}">Undo ${loop.state === "added" ? "the addition" : "the rejection"}</button>`;
  }
  return `<button data-reject="${loop.query_image},${loop.match_image}">Reject</button>`;
}

function poseText(pose) {
  if (!pose) return "not estimated (no camera intrinsics then)";
  let text = `${pose.inliers} inliers`;
  if (pose.translation) {
    text += `, t = (${pose.translation.map(v => v.toFixed(3)).join(", ")})${pose.metric ? " m" : " (direction)"}`;
    text += `, q = (${pose.quaternion_xyzw.map(v => v.toFixed(3)).join(", ")})`;
  } else if (pose.reason) {
    text += `, no pose: ${esc(pose.reason)}`;
  }
  return text;
}

async function loadSummary() {
  summary = await api("/api/summary");
  document.getElementById("editing").textContent =
    summary.read_only ? `read-only: ${summary.read_only_reason}`
      : token ? "editing allowed (token given)" : "view only: open the address memloop view printed to edit";
}

async function mapPage() {
  const s = summary;
  let html = `<h1>${esc(s.path)}</h1><table>
    <tr><th>images</th><td>${s.images}</td></tr>
    <tr><th>locations</th><td>${s.ltm_locations} in LTM, ${s.checkpoint_locations} in STM/WM at the last checkpoint</td></tr>
    <tr><th>words</th><td>${s.words >= 0 ? s.words : "not counted here (memloop inspect counts them)"}</td></tr>
    <tr><th>links</th><td>${s.neighbour_links} neighbour, ${s.loop_closure_links} loop closure</td></tr>
    <tr><th>loop closures</th><td><a href="#/loops">${s.loop_closures}</a> (${s.detected_loop_closures} detected, ${s.rejected_loop_closures} rejected, ${s.edits} edits)</td></tr>
    <tr><th>integrity</th><td>${esc(s.integrity)}</td></tr></table>
    <h2>Sessions</h2><table><tr><th>session</th><th>images</th><th>first</th><th>last</th></tr>`;
  for (const session of s.sessions) {
    html += `<tr><td><a href="#/session/${session.id}">${session.id}</a></td><td>${session.images}</td>
      <td>${imageLabel(session.first_image, session.first_name)}</td><td>${imageLabel(session.last_image, session.last_name)}</td></tr>`;
  }
  html += `</table><details><summary>Parameters (${Object.keys(s.parameters).length})</summary><table>`;
  for (const [name, value] of Object.entries(s.parameters)) html += `<tr><td>${esc(name)}</td><td>${esc(value)}</td></tr>`;
  return html + "</table></details>";
}

async function loopsPage(offset) {
  const page = await api(`/api/loop_closures?offset=${offset}&limit=${PAGE}`);
  let html = `<h1>Loop closures</h1><p>${page.in_force} in force of ${page.total} listed (detected, rejected, added).</p>${pager("#/loops", offset, page.total, PAGE)}
    <table><tr><th>#</th><th>state</th><th>query</th><th>match</th><th>value</th><th></th></tr>`;
  for (const loop of page.loop_closures) {
    html += `<tr class="loop" id="loop-${loop.n}"><td><a href="#/loop/${loop.n}">${loop.n}</a></td>
      <td class="state-${loop.state}">${loop.state}</td>
      <td><a href="#/loop/${loop.n}">${thumb(loop.query_image, loop.query_name)}</a>${imageLabel(loop.query_image, loop.query_name)}</td>
      <td><a href="#/loop/${loop.n}">${matchThumb(loop)}</a>${matchLabel(loop)}</td>
      <td>${loop.state === "added" ? "by hand" : loop.probability.toFixed(3)}</td><td>${loopButtons(loop)}</td></tr>`;
  }
  return html + "</table>";
}

function pager(base, offset, total, size) {
  const parts = [];
  if (offset > 0) parts.push(`<a href="${base}?offset=${Math.max(0, offset - size)}">previous</a>`);
  parts.push(`${total ? offset + 1 : 0}-${Math.min(total, offset + size)} of ${total}`);
  if (offset + size < total) parts.push(`<a href="${base}?offset=${offset + size}">next</a>`);
  return `<div class="pager">${parts.join(" · ")}</div>`;
}

async function loopPage(n) {
  const page = await api(`/api/loop_closures?offset=${n}&limit=1`);
  const loop = page.loop_closures[0];
  if (!loop) return `<p class="error">No loop closure ${n}.</p>`;
  const figure = (index, name, location, robot) => `<figure>${summary.images_folder && !robot ? `<img src="/api/images/${index}" alt="${esc(name || index)}">` : ""}
    <figcaption>${robot ? `robot ${esc(robot)} #${index}` : imageLabel(index, name)}, location <a href="#/location/${location}">${location}</a></figcaption></figure>`;
  return `<h1>Loop closure ${n} <span class="state-${loop.state}">${loop.state}</span></h1>
    <p>${loop.state === "added" ? `added by hand (edit ${loop.edit})` : `accepted at value ${loop.probability.toFixed(3)}`}${loop.state === "rejected" ? `, rejected by edit ${loop.edit}` : ""}.
    Geometry: ${poseText(loop.pose)}.</p><p>${loopButtons(loop)}</p>
    <div class="pair">${figure(loop.query_image, loop.query_name, loop.query_location)}${figure(loop.match_image, loop.match_name, loop.match_location, loop.match_robot)}</div>
    <p>${n > 0 ? `<a href="#/loop/${n - 1}">previous</a> · ` : ""}${n + 1 < page.total ? `<a href="#/loop/${n + 1}">next</a>` : ""}</p>`;
}

async function matrixPage() {
  const page = await api(`/api/loop_closures?offset=0&limit=100000`);
  setTimeout(() => drawMatrix(page.loop_closures), 0);
  return `<h1>Loop closures: query × match</h1><p>Each point is a loop closure (green detected, blue added,
    red rejected); the diagonal is time. Click a point to see its images.</p><canvas id="matrix" width="640" height="640"></canvas>`;
}

function drawMatrix(loops) {
  const canvas = document.getElementById("matrix");
  if (!canvas) return;
  const context = canvas.getContext("2d");
  const last = Math.max(1, summary.last_image);
  const size = canvas.width - 40;
  const at = index => 20 + size * index / last;
  context.strokeStyle = "#ccc";
  context.beginPath(); context.moveTo(at(0), at(0)); context.lineTo(at(last), at(last)); context.stroke();
  const colour = {detected: "#1b6e2f", added: "#1d5fa8", rejected: "#a61b1b"};
  loops = loops.filter(loop => !loop.match_robot);  // this map's images only
  for (const loop of loops) {
    context.fillStyle = colour[loop.state];
    context.fillRect(at(loop.match_image) - 2, at(loop.query_image) - 2, 5, 5);
  }
  canvas.onclick = event => {
    const box = canvas.getBoundingClientRect();
    const x = event.clientX - box.left, y = event.clientY - box.top;
    let best = null, distance = 12;
    for (const loop of loops) {
      const d = Math.hypot(at(loop.match_image) - x, at(loop.query_image) - y);
      if (d < distance) { best = loop; distance = d; }
    }
    if (best) location.hash = `#/loop/${best.n}`;
  };
}

async function graphPage() {
  let positions;
  try {
    positions = (await api("/api/positions")).positions;
  } catch (error) {
    return `<h1>Graph</h1><p>${esc(error.message)}: a TUM file (time tx ty tz qx qy qz qw) of the
      images' time stamps, odometry or ground truth. The <a href="#/matrix">matrix</a> shows the loop
      closures by time meanwhile.</p>`;
  }
  const page = await api(`/api/loop_closures?offset=0&limit=100000`);
  setTimeout(() => drawGraph(positions, page.loop_closures), 0);
  return `<h1>Graph: ${positions.length} images by position</h1><p>Seen from above the two axes
    along which the trajectory spreads most; loop closures join their two images (green detected,
    blue added, red rejected). Click a loop closure to see its images.</p>
    <canvas id="graph" width="800" height="640"></canvas>`;
}

function drawGraph(positions, loops) {
  const canvas = document.getElementById("graph");
  if (!canvas) return;
  const at = new Map(positions.map(p => [p[0], p]));
  const spread = [1, 2, 3].map(axis => {
    const values = positions.map(p => p[axis]);
    return {axis, low: Math.min(...values), high: Math.max(...values)};
  }).sort((a, b) => (b.high - b.low) - (a.high - a.low));
  const [u, v] = spread;
  const scale = Math.min((canvas.width - 40) / Math.max(u.high - u.low, 1e-9),
                         (canvas.height - 40) / Math.max(v.high - v.low, 1e-9));
  const xy = p => [20 + (p[u.axis] - u.low) * scale, canvas.height - 20 - (p[v.axis] - v.low) * scale];
  const context = canvas.getContext("2d");
  context.strokeStyle = "#999";
  context.beginPath();
  positions.forEach((p, i) => {
    const [x, y] = xy(p);
    if (i > 0 && p[0] === positions[i - 1][0] + 1) context.lineTo(x, y); else context.moveTo(x, y);
  });
  context.stroke();
  const colour = {detected: "#1b6e2f", added: "#1d5fa8", rejected: "#a61b1b"};
  const drawn = [];
  for (const loop of loops) {
    const a = at.get(loop.query_image), b = at.get(loop.match_image);
    if (!a || !b || loop.match_robot) continue;
    const [x1, y1] = xy(a), [x2, y2] = xy(b);
    context.strokeStyle = colour[loop.state];
    context.beginPath(); context.moveTo(x1, y1); context.lineTo(x2, y2); context.stroke();
    context.fillStyle = colour[loop.state];
    context.fillRect(x1 - 2, y1 - 2, 4, 4);
    drawn.push({loop, x: (x1 + x2) / 2, y: (y1 + y2) / 2});
  }
  canvas.onclick = event => {
    const box = canvas.getBoundingClientRect();
    const x = event.clientX - box.left, y = event.clientY - box.top;
    let best = null, distance = 12;
    for (const d of drawn) {
      const far = Math.hypot(d.x - x, d.y - y);
      if (far < distance) { best = d.loop; distance = far; }
    }
    if (best) location.hash = `#/loop/${best.n}`;
  };
}

async function sessionPage(session, offset) {
  const page = await api(`/api/images?session=${session}&offset=${offset}&limit=${IMAGES_PAGE}`);
  let html = `<h1>Session ${session}</h1>${chooser()}${pager(`#/session/${session}`, offset, page.total, IMAGES_PAGE)}<div class="grid">`;
  for (const image of page.images) {
    const picked = chosen.includes(image.index) ? " chosen" : "";
    html += `<figure class="${picked}"><a href="#/location/${image.location}">${thumb(image.index, image.name)}</a>
      <figcaption>${imageLabel(image.index, image.name)}<br>location ${image.location ?? "?"}
      ${canEdit() ? `<button data-choose="${image.index}">${picked ? "unpick" : "pick"}</button>` : ""}</figcaption></figure>`;
  }
  return html + "</div>";
}

function chooser() {
  if (!canEdit()) return "";
  if (chosen.length < 2) return `<p class="muted">Pick two images to add a loop closure between them (${chosen.length} picked).</p>`;
  return `<p>Picked images ${chosen[0]} and ${chosen[1]}: <button data-add="${chosen[0]},${chosen[1]}">Add a loop closure</button></p>`;
}

async function locationPage(id) {
  const place = await api(`/api/locations/${id}`);
  const origin = place.robot
    ? `a place of robot ${esc(place.robot)} (its images ${place.robot_images.map(i => `#${i}`).join(", ")})`
    : `view (keypoints) of image ${place.view_image}`;
  let html = `<h1>Location ${place.id}</h1><p>${esc(place.in)}; weight ${place.weight}; ${place.words} words;
    ${origin}.</p><div class="grid">`;
  for (const image of place.images) {
    html += `<figure>${thumb(image.index, image.name)}<figcaption>${imageLabel(image.index, image.name)}</figcaption></figure>`;
  }
  const links = ids => ids.map(l => `<a href="#/location/${l}">${l}</a>`).join(", ") || "none";
  html += `</div><p>Neighbours: ${links(place.neighbours)}. Loop closure links: ${links(place.loop_closure_links)}.</p>
    <h2>Its loop closures</h2><table>`;
  for (const loop of place.loop_closures) {
    html += `<tr><td class="state-${loop.state}">${loop.state}</td><td>${imageLabel(loop.query_image, loop.query_name)} → ${matchLabel(loop)}</td>
      <td>${loop.state === "added" ? "by hand" : loop.probability.toFixed(3)}</td><td>${poseText(loop.pose)}</td></tr>`;
  }
  return html + "</table>";
}

async function editsPage() {
  const page = await api("/api/edits");
  let html = `<h1>Edits</h1><table><tr><th>#</th><th>what</th><th>who</th><th>when</th><th></th></tr>`;
  for (const e of page.edits) {
    const what = e.action === "undo" ? `undo of edit ${e.undone_edit}` : `${e.action} ${e.query_image} – ${e.match_image}`;
    html += `<tr><td>${e.id}</td><td>${esc(what)}${e.undone ? " (undone)" : ""}</td><td>${esc(e.who)}</td>
      <td>${new Date(e.time * 1000).toISOString().replace("T", " ").slice(0, 19)} UTC</td>
      <td>${canEdit() && e.action !== "undo" && !e.undone ? `<button data-undo="${e.id}">Undo</button>` : ""}</td></tr>`;
  }
  return html + "</table>";
}

async function route() {
  const [path, query] = (location.hash.slice(1) || "/").split("?");
  const offset = Number(new URLSearchParams(query || "").get("offset") || 0);
  const parts = path.split("/").filter(Boolean);
  const page = document.getElementById("page");
  try {
    if (!summary) await loadSummary();
    let html;
    if (parts[0] === "loops") html = await loopsPage(offset);
    else if (parts[0] === "loop") html = await loopPage(Number(parts[1]));
    else if (parts[0] === "matrix") html = await matrixPage();
    else if (parts[0] === "graph") html = await graphPage();
    else if (parts[0] === "session") html = await sessionPage(Number(parts[1]), offset);
    else if (parts[0] === "location") html = await locationPage(Number(parts[1]));
    else if (parts[0] === "edits") html = await editsPage();
    else html = await mapPage();
    page.innerHTML = html;
    page.dataset.view = parts[0] || "map";
  } catch (error) {
    page.innerHTML = `<p class="error">${esc(error.message)}</p>`;
  }
}

document.addEventListener("click", event => {
  const target = event.target;
  if (target.dataset.reject) {
    const [query, match] = target.dataset.reject.split(",").map(Number);
    edit({action: "reject", query_image: query, match_image: match});
  } else if (target.dataset.undo) {
    edit({action: "undo", edit: Number(target.dataset.undo)});
  } else if (target.dataset.add) {
    const [query, match] = target.dataset.add.split(",").map(Number);
    chosen = [];
    edit({action: "add", query_image: query, match_image: match});
  } else if (target.dataset.choose) {
    const index = Number(target.dataset.choose);
    chosen = chosen.includes(index) ? chosen.filter(i => i !== index) : [...chosen.slice(-1), index];
    route();
  }
});

document.getElementById("search").addEventListener("submit", async event => {
  event.preventDefault();
  try {
    const image = await api(`/api/find?q=${encodeURIComponent(document.getElementById("search-text").value)}`);
    location.hash = `#/location/${image.location}`;
  } catch (error) {
    show(`<span class="error">${esc(error.message)}</span>`);
  }
});

window.addEventListener("hashchange", () => { show(""); route(); });
route();
