// The tileset beside this page in CesiumJS, offline: a plain globe without imagery or terrain,
// buildings picked on click (their properties and tags in the info box) and coloured by height
// on request (?style=height or the panel). window.cityshade tells scripts how far it got.
"use strict";

const GLOBE = "#7d8471"; // the plain ground colour where there is no tile
const HEIGHTS = [  // [lowest height in metres, colour]: the "by height" style, tallest first
  [40, "#b30000"], [25, "#e34a33"], [15, "#fc8d59"], [8, "#fdcc8a"], [0, "#fef0d9"],
];
const state = (window.cityshade = { ready: false, error: null, picked: null, style: null, frames: 0 });

function escapeHtml(text) {
  return String(text).replace(/[&<>"']/g, (c) => `&#${c.charCodeAt(0)};`);
}

function heightStyle() {
  const conditions = HEIGHTS.map(([low, colour]) => [`\${height} >= ${low}`, `color('${colour}')`]);
  const unknown = ["${height} === undefined", "color('white')"];  // no data (the schema's noData)
  return new Cesium.Cesium3DTileStyle({ color: { conditions: [unknown, ...conditions, ["true", "color('white')"]] } });
}

function setStyle(tileset, name) {
  state.style = name;
  tileset.style = name === "height" ? heightStyle() : undefined;
  document.getElementById("style").value = name;
  document.getElementById("legend").innerHTML = name !== "height" ? "" : HEIGHTS.map(
    ([low, colour]) => ` <span style="color:${colour}">&#9632;</span> ${low} m`).join("");
}

function properties(feature) {
  const rows = {};
  for (const id of feature.getPropertyIds()) rows[id] = feature.getProperty(id);
  return rows;
}

function describe(rows) {
  let tags = {};
  try { tags = JSON.parse(rows.tags || "{}"); } catch (e) { tags = { tags: rows.tags }; }
  const line = (k, v) => `<tr><th>${escapeHtml(k)}</th><td>${escapeHtml(v)}</td></tr>`;
  const own = Object.entries(rows).filter(([k]) => k !== "tags").map(([k, v]) => line(k, v));
  const tagged = Object.entries(tags).map(([k, v]) => line(k, v));
  return `<table class="cesium-infoBox-defaultTable">${own.join("")}` +
    `<tr><th colspan="2">tags</th></tr>${tagged.join("")}</table>`;
}

function selection(viewer) {
  // select(feature): its properties and tags in the info box and highlighted; anything else clears
  const selected = new Cesium.Entity();
  let highlighted = null, highlightedColour = null;
  return (feature) => {
    if (highlighted) highlighted.color = highlightedColour;
    highlighted = null;
    if (!(feature instanceof Cesium.Cesium3DTileFeature)) {
      viewer.selectedEntity = undefined;
      state.picked = null;
      return;
    }
    const rows = properties(feature);
    state.picked = rows;
    highlighted = feature;
    highlightedColour = Cesium.Color.clone(feature.color);
    feature.color = Cesium.Color.YELLOW;
    selected.name = `${rows.kind || "building"} ${rows.source_id || ""}`;
    selected.description = describe(rows);
    viewer.selectedEntity = selected;
  };
}

function firstBuilding(tile) {  // a building of the first tile drawn (scripts check the info box with it)
  const content = tile.content;
  if (content && content.featuresLength > 0) return content.getFeature(0);
  for (const child of tile.children) {
    const found = firstBuilding(child);
    if (found) return found;
  }
  return null;
}

async function main() {
  const viewer = (window.cityshadeViewer = new Cesium.Viewer("globe", {
    baseLayer: false, terrainProvider: new Cesium.EllipsoidTerrainProvider(),
    baseLayerPicker: false, geocoder: false, animation: false, timeline: false,
    sceneModePicker: false, navigationHelpButton: false, fullscreenButton: false, homeButton: false,
  }));
  viewer.scene.renderError.addEventListener((scene, error) => { state.error = String(error && error.stack || error); });
  const globe = viewer.scene.globe;
  globe.baseColor = Cesium.Color.fromCssColorString(GLOBE);
  globe.showGroundAtmosphere = false;
  viewer.scene.fog.enabled = false;
  const tileset = await Cesium.Cesium3DTileset.fromUrl("tileset.json");
  viewer.scene.primitives.add(tileset);
  const style = new URLSearchParams(window.location.search).get("style") || "facades";
  setStyle(tileset, style);
  document.getElementById("style").onchange = (event) => setStyle(tileset, event.target.value);
  const select = selection(viewer);
  new Cesium.ScreenSpaceEventHandler(viewer.scene.canvas).setInputAction(
    (click) => select(viewer.scene.pick(click.position)), Cesium.ScreenSpaceEventType.LEFT_CLICK);
  state.selectFirst = () => select(firstBuilding(tileset.root));
  const radius = tileset.boundingSphere.radius;
  await viewer.zoomTo(tileset, new Cesium.HeadingPitchRange(0.6, -0.6, radius * 2.2));
  viewer.scene.postRender.addEventListener(() => { state.frames += 1; });
  tileset.allTilesLoaded.addEventListener(() => {
    const loaded = state.frames;  // a few frames after the last tile, so the picture is drawn
    const wait = viewer.scene.postRender.addEventListener(() => {
      if (state.frames >= loaded + 5) { wait(); state.ready = true; }
    });
  });
}

main().catch((error) => {
  state.error = String(error && error.stack || error);
  console.error(state.error);
});
