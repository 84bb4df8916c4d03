// The "materials" section (SCENE_FORMAT.md "materials.NAME.*").
#include "tear/materials/registry.h"
#include "tear/scene/scene_parts.h"

#include <cmath>

namespace tear::scene_detail {

namespace {

// A scalar (applies to the first fiber, the rest 0) or an array of 1..n numbers.
void scalar_or_array(const Reader& r, const json& v, const std::string& path, int n,
                     double* out) {
  for (int i = 0; i < n; ++i) out[i] = 0;
  if (v.is_number()) {
    out[0] = r.as_number(v, path);
  } else if (v.is_array() && v.size() >= 1 && int(v.size()) <= n) {
    for (size_t i = 0; i < v.size(); ++i) out[i] = r.as_number(v[i], index_path(path, i));
  } else {
    r.fail(path, "must be a number or an array of " +
                     (n == 1 ? std::string("1 number") : "1 to " + std::to_string(n) + " numbers") +
                     ", got " + (v.is_array() ? entries(v.size()) : type_desc(v)));
  }
}

// "only qr_aniso has" / "only a, b have": the registered models with `trait`, for errors.
std::string only_models(bool ModelTraits::*trait, const char* verb_one, const char* verb_many) {
  int count = 0;
  for (const ModelTraits& t : kModelTraits) count += t.*trait ? 1 : 0;
  return "only " + model_names(trait) + " " + (count == 1 ? verb_one : verb_many);
}

json parse_damage_spec(const Reader& r, const json& m, const std::string& path, DamageParams* d) {
  const json* j = r.find(m, "damage");
  if (!j) return nullptr;
  std::string p = key_path(path, "damage");
  r.object(*j, p, {"sigma_c", "eta", "residual", "alpha", "surface_anisotropy"});
  d->enabled = true;
  d->sigma_c = r.number(*j, p, "sigma_c");
  r.positive(d->sigma_c, key_path(p, "sigma_c"));
  d->eta = r.number(*j, p, "eta");
  r.positive(d->eta, key_path(p, "eta"));
  d->residual = r.number(*j, p, "residual", 0.0);
  r.check(d->residual >= 0 && d->residual < 1, key_path(p, "residual"),
          "must be in [0, 1), got " + num_str(d->residual));
  // Per-fiber weights (0 when absent), each finite and above -1 (alpha: -1 allowed too).
  auto weights = [&](const char* key, bool minus_one_allowed, double* out) {
    const json* w = r.find(*j, key);
    out[0] = out[1] = 0;
    if (w) scalar_or_array(r, *w, key_path(p, key), 2, out);
    for (int i = 0; i < 2; ++i)
      r.check(std::isfinite(out[i]) && (out[i] > -1 || (minus_one_allowed && out[i] == -1)),
              w && w->is_array() ? index_path(key_path(p, key), i) : key_path(p, key),
              std::string("must be a number ") + (minus_one_allowed ? ">=" : ">") +
                  " -1, got " + num_str(out[i]));
  };
  weights("alpha", true, d->alpha);
  weights("surface_anisotropy", false, d->surface);
  return {{"sigma_c", d->sigma_c},
          {"eta", d->eta},
          {"residual", d->residual},
          {"alpha", {d->alpha[0], d->alpha[1]}},
          {"surface_anisotropy", {d->surface[0], d->surface[1]}}};
}

// "plasticity": null (elastic), von Mises or Drucker-Prager on the Hencky stress of (E, nu)
// (materials/plasticity.h).
json parse_plasticity(const Reader& r, const json& m, const std::string& path, Real E, Real nu,
                      PlasticParams* out) {
  const json* j = r.find(m, "plasticity");
  if (!j || j->is_null()) return nullptr;
  const std::string p = key_path(path, "plasticity");
  if (!j->is_object()) r.fail(p, "must be null or an object, got " + type_desc(*j));
  const int type = r.choice(*j, p, "type", {"von_mises", "drucker_prager"});
  if (type == 0) {
    r.object(*j, p, {"type", "yield_stress", "hardening"});
    const double yield = r.number(*j, p, "yield_stress");
    r.positive(yield, key_path(p, "yield_stress"));
    const double hardening = r.number(*j, p, "hardening", 0.0);
    r.non_negative(hardening, key_path(p, "hardening"));
    *out = von_mises(E, nu, Real(yield), Real(hardening));
    return {{"type", "von_mises"}, {"yield_stress", yield}, {"hardening", hardening}};
  }
  r.object(*j, p, {"type", "friction_angle", "cohesion", "volume_correction"});
  const double angle = r.number(*j, p, "friction_angle");
  r.check(angle > 0 && angle < 90, key_path(p, "friction_angle"),
          "must be in (0, 90) degrees, got " + num_str(angle));
  const double cohesion = r.number(*j, p, "cohesion", 0.0);
  r.non_negative(cohesion, key_path(p, "cohesion"));
  const bool correct = r.boolean(*j, p, "volume_correction", true);
  *out = drucker_prager(E, nu, Real(angle), Real(cohesion), correct);
  return {{"type", "drucker_prager"},
          {"friction_angle", angle},
          {"cohesion", cohesion},
          {"volume_correction", correct}};
}

// normal_stiffness (k), shear_stiffness (gamma) and friction (c_F, or friction_angle in degrees:
// c_F = tan) of a codimensional model; refused for the others.
json parse_codim_keys(const Reader& r, const json& m, const std::string& path,
                      const std::string& model_str, MaterialParams* p) {
  const char* keys[] = {"normal_stiffness", "shear_stiffness", "friction", "friction_angle",
                        "bending_modulus"};
  if (model_codimension(p->model) == 0) {
    for (const char* key : keys)
      r.check(!r.find(m, key), key_path(path, key),
              "only for the codimensional models (surface_qr, curve_qr), not \"" + model_str + "\"");
    return json::object();
  }
  p->normal_stiffness = Real(r.number(m, path, "normal_stiffness", double(p->normal_stiffness)));
  r.positive(p->normal_stiffness, key_path(path, "normal_stiffness"));
  p->shear_stiffness = Real(r.number(m, path, "shear_stiffness", double(p->shear_stiffness)));
  r.positive(p->shear_stiffness, key_path(path, "shear_stiffness"));
  if (r.find(m, "friction_angle")) {
    r.check(!r.find(m, "friction"), key_path(path, "friction_angle"),
            "give \"friction\" (the coefficient) or \"friction_angle\" (degrees), not both");
    const double angle = r.number(m, path, "friction_angle");
    r.check(angle >= 0 && angle < 90, key_path(path, "friction_angle"),
            "must be in [0, 90) degrees, got " + num_str(angle));
    p->friction = Real(std::tan(angle * 3.14159265358979323846 / 180));
  } else {
    p->friction = Real(r.number(m, path, "friction", double(p->friction)));
    r.non_negative(p->friction, key_path(path, "friction"));
  }
  p->bending_modulus = Real(r.number(m, path, "bending_modulus", 0.0));
  r.non_negative(p->bending_modulus, key_path(path, "bending_modulus"));
  return {{"normal_stiffness", p->normal_stiffness},
          {"shear_stiffness", p->shear_stiffness},
          {"friction", p->friction},
          {"bending_modulus", p->bending_modulus}};
}

MaterialSpec parse_material(const Reader& r, const std::string& name, const json& m,
                            json* out) {
  std::string path = key_path("materials", name);
  r.object(m, path,
           {"model", "E", "nu", "rho", "fiber_scale", "lambda_convention", "damage", "plasticity",
            "inextensible", "inextensibility_relaxation", "normal_stiffness", "shear_stiffness",
            "friction", "friction_angle", "bending_modulus", "rayleigh"});
  MaterialSpec spec;
  spec.name = name;
  std::string model_str = r.string(m, path, "model");
  Model model;
  if (!parse_model(model_str, &model))
    r.fail(key_path(path, "model"),
           "unknown model \"" + model_str + "\" (expected one of: " + model_names() + ")");
  double E = r.number(m, path, "E");
  r.positive(E, key_path(path, "E"));
  double nu = r.number(m, path, "nu");
  r.check(nu > -1 && nu < 0.5, key_path(path, "nu"), "must be in (-1, 0.5), got " + num_str(nu));
  double rho = r.number(m, path, "rho");
  r.positive(rho, key_path(path, "rho"));

  // fiber_scale: [gamma1] in 2D, [gamma1, gamma2] in 3D; a scalar sets gamma1 only.
  // 2D also takes [gamma1, 0], as in SCENE_FORMAT.md's example (only a1 is stiffened in 2D).
  int nfs = r.dim - 1;
  double fs[2] = {0, 0};
  if (const json* f = r.find(m, "fiber_scale")) {
    std::string fp = key_path(path, "fiber_scale");
    bool zero_pad = r.dim == 2 && f->is_array() && f->size() == 2;
    if (f->is_array() && int(f->size()) != nfs && !zero_pad)
      r.fail(fp, "must be an array of " + std::to_string(nfs) + " number" + (nfs > 1 ? "s" : "") +
                     " in " + std::to_string(r.dim) + "D, got " + entries(f->size()));
    scalar_or_array(r, *f, fp, 2, fs);
    for (int i = 0; i < 2; ++i) r.non_negative(fs[i], f->is_array() ? index_path(fp, i) : fp);
    if (zero_pad)
      r.check(fs[1] == 0, index_path(fp, 1),
              "must be 0 in 2D (only a1 has a fiber stiffness), got " + num_str(fs[1]));
  }
  // Fiber terms and a degradable energy only where the model's traits (materials/registry.h)
  // say so; refuse rather than ignore.
  const ModelTraits& traits = model_traits(model);
  if (!traits.has_fiber_stiffness)
    r.check(fs[0] == 0 && fs[1] == 0, key_path(path, "fiber_scale"),
            "must be 0 for the isotropic model \"" + model_str + "\" (" +
                only_models(&ModelTraits::has_fiber_stiffness, "has", "have") +
                " fiber stiffness)");
  if (!traits.degraded_by_damage)
    r.check(!r.find(m, "damage"), key_path(path, "damage"),
            "not implemented yet for model \"" + model_str + "\" (" +
                only_models(&ModelTraits::degraded_by_damage, "is", "are") +
                " degraded by damage)");
  spec.fiber_scale[0] = Real(fs[0]);
  spec.fiber_scale[1] = Real(fs[1]);
  spec.params = make_material(model, Real(E), Real(nu), Real(rho), Real(fs[0]), Real(fs[1]));
  // qr_aniso's energy lambda: tear's lambda_Lame + mu (small strains match E, nu) or, with
  // "paper", lambda_Lame itself, as the paper's energy reads with Table 1's E, nu.
  const int convention = r.choice(m, path, "lambda_convention", {"small_strain", "paper"}, 0);
  if (convention == 1) {
    r.check(model == Model::QrAniso, key_path(path, "lambda_convention"),
            "\"paper\" is only for qr_aniso (the other models use the Lame lambda of E, nu "
            "either way)");
    spec.params.lambda = lame_lambda(Real(E), Real(nu));
  }

  // The codimensional models' own keys (materials/material.h): physical defaults from E, nu.
  json codim = parse_codim_keys(r, m, path, model_str, &spec.params);

  json damage = parse_damage_spec(r, m, path, &spec.damage);
  json plasticity = parse_plasticity(r, m, path, Real(E), Real(nu), &spec.plasticity);
  InextensibleParams& inx = spec.inextensibility;
  inx.enabled = r.boolean(m, path, "inextensible", false);
  json relaxation = nullptr;
  if (r.find(m, "inextensibility_relaxation")) {
    const std::string rp = key_path(path, "inextensibility_relaxation");
    inx.relaxation = r.number(m, path, "inextensibility_relaxation");
    r.positive(inx.relaxation, rp);
    r.check(inx.enabled, rp, "relaxes the inextensibility constraint: set \"inextensible\": true");
    relaxation = inx.relaxation;
  }

  json rayleigh = nullptr;
  if (const json* d = r.find(m, "rayleigh")) {
    const std::string dp = key_path(path, "rayleigh");
    r.object(*d, dp, {"alpha", "beta"});
    spec.rayleigh_alpha = r.number(*d, dp, "alpha", 0.0);
    spec.rayleigh_beta = r.number(*d, dp, "beta", 0.0);
    r.non_negative(spec.rayleigh_alpha, key_path(dp, "alpha"));
    r.non_negative(spec.rayleigh_beta, key_path(dp, "beta"));
    rayleigh = {{"alpha", spec.rayleigh_alpha}, {"beta", spec.rayleigh_beta}};
  }

  if (traits.codimension > 0) {
    // Their friction is their return map; nothing else bends or binds them yet.
    for (const char* key : {"plasticity", "inextensible"})
      if (const json* v = r.find(m, key))
        r.check(v->is_null() || *v == false, key_path(path, key),
                "not for the codimensional model \"" + model_str +
                    "\" (its friction return map is its plasticity: see \"friction\")");
  }

  json fsj = json::array();
  for (int i = 0; i < nfs; ++i) fsj.push_back(fs[i]);
  *out = {{"model", model_str}, {"E", E},          {"nu", nu},
          {"rho", rho},         {"fiber_scale", fsj},
          {"lambda_convention", convention == 1 ? "paper" : "small_strain"},
          {"damage", damage},
          {"plasticity", plasticity}, {"inextensible", inx.enabled},
          {"inextensibility_relaxation", relaxation}};
  if (!rayleigh.is_null()) (*out)["rayleigh"] = rayleigh;
  out->update(codim);
  return spec;
}

}  // namespace

json parse_materials(const Reader& r, const json& doc, Scene* scene) {
  const json* ms = r.find(doc, "materials");
  if (!ms) r.fail("materials", "required");
  if (!ms->is_object())
    r.fail("materials", "must be an object of NAME: {...}, got " + type_desc(*ms));
  r.check(ms->size() <= 65535, "materials", "too many materials (at most 65535)");
  json out = json::object();
  for (auto it = ms->begin(); it != ms->end(); ++it) {  // name order (std::map)
    r.check(!it.key().empty(), "materials", "material names must not be empty");
    json resolved;
    scene->materials.push_back(parse_material(r, it.key(), it.value(), &resolved));
    out[it.key()] = resolved;
  }
  return out;
}

int ppc_root(int ppc, int dim) {
  for (int k = 1; k <= ppc; ++k) {
    int p = dim == 2 ? k * k : k * k * k;
    if (p == ppc) return k;
    if (p > ppc) break;
  }
  return 0;
}

}  // namespace tear::scene_detail
