// CAAML v6.0 SnowProfileIACS (caaml.org; what SnowPilot and niViz export), read with libxml2 and
// XPath. The namespace of the root decides: http://caaml.org/Schemas/SnowProfileIACS/v6.0.x; any
// other root (another schema, an older CAAML, a foreign XML file) is refused. Units are those the
// schema fixes and each element states in its uom attribute: cm for depths, thicknesses and PST
// lengths, mm for grain sizes, kgm-3 for densities, deg for the slope; another uom is refused, not
// converted (it is a file written for another schema, or a mistake).
// The network and external entities are never fetched (XML_PARSE_NONET, no entity substitution).
#include "profile/profile_reader.h"

#include "util/format.h"

#include <libxml/parser.h>
#include <libxml/xpath.h>
#include <libxml/xpathInternals.h>

#include <cmath>
#include <cstdlib>
#include <memory>

namespace anticrack::profile
{
  namespace
  {
    constexpr const char *caaml_namespace_prefix = "http://caaml.org/Schemas/SnowProfileIACS/v6.0.";
    constexpr double centimetre = 0.01;

    /// The parsed document and its XPath context, with the caaml namespace of its root registered as `c`.
    class CaamlDocument
    {
    public:
      explicit CaamlDocument(const std::string &file) : file_(file)
      {
        xmlResetLastError();
        document_.reset(xmlReadFile(file.c_str(), nullptr, XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING));
        if (!document_)
        {
          const xmlError *e = xmlGetLastError();
          std::string reason = e && e->message ? e->message : "unknown error";
          while (!reason.empty() && (reason.back() == '\n' || reason.back() == ' '))
            reason.pop_back();
          throw ProfileError(file + ": not well-formed XML" +
                             (e ? " (line " + std::to_string(e->line) + ": " + reason + ")" : std::string()) +
                             "; a torn or truncated file?");
        }
        const xmlNode *root = xmlDocGetRootElement(document_.get());
        const std::string ns = root && root->ns && root->ns->href ? reinterpret_cast<const char *>(root->ns->href) : "";
        const std::string name = root ? reinterpret_cast<const char *>(root->name) : "";
        if (name != "SnowProfile" || ns.rfind(caaml_namespace_prefix, 0) != 0)
          throw ProfileError(file + ": the root element is {" + ns + "}" + name + ", not a CAAML v6.0 SnowProfile (" +
                             caaml_namespace_prefix + "x); another schema or an older CAAML is not read");
        context_.reset(xmlXPathNewContext(document_.get()));
        xmlXPathRegisterNs(context_.get(), BAD_CAST "c", root->ns->href);
      }

      /// The element nodes at `path` below `node` (the document's root if null).
      std::vector<xmlNode *> nodes(const std::string &path, xmlNode *node = nullptr) const
      {
        context_->node = node ? node : xmlDocGetRootElement(document_.get());
        std::unique_ptr<xmlXPathObject, decltype(&xmlXPathFreeObject)> result(
          xmlXPathEvalExpression(BAD_CAST path.c_str(), context_.get()), xmlXPathFreeObject);
        std::vector<xmlNode *> found;
        if (result && result->nodesetval)
          for (int k = 0; k < result->nodesetval->nodeNr; ++k)
            found.push_back(result->nodesetval->nodeTab[k]);
        return found;
      }

      /// The one element at `path` below `node`, or null.
      xmlNode *node(const std::string &path, xmlNode *at) const
      {
        const std::vector<xmlNode *> found = nodes(path, at);
        return found.empty() ? nullptr : found.front();
      }

      const std::string &file() const { return file_; }
      xmlNode *root() const { return xmlDocGetRootElement(document_.get()); }

    private:
      std::string file_;
      std::unique_ptr<xmlDoc, decltype(&xmlFreeDoc)> document_{nullptr, xmlFreeDoc};
      std::unique_ptr<xmlXPathContext, decltype(&xmlXPathFreeContext)> context_{nullptr, xmlXPathFreeContext};
    };

    std::string text_of(const xmlNode *node)
    {
      if (!node)
        return "";
      std::unique_ptr<xmlChar, decltype(xmlFree)> content(xmlNodeGetContent(node), xmlFree);
      std::string text = content ? reinterpret_cast<const char *>(content.get()) : "";
      const auto first = text.find_first_not_of(" \t\r\n");
      const auto last = text.find_last_not_of(" \t\r\n");
      return first == std::string::npos ? "" : text.substr(first, last - first + 1);
    }

    std::string attribute(const xmlNode *node, const char *name)
    {
      std::unique_ptr<xmlChar, decltype(xmlFree)> value(xmlGetProp(node, BAD_CAST name), xmlFree);
      return value ? reinterpret_cast<const char *>(value.get()) : "";
    }

    /// The number in `node` (`where` and `field` name it in messages), its uom attribute (on it or on
    /// `uom_node`) required to be `unit`.
    double number(const CaamlDocument &doc, const xmlNode *node, const std::string &where, const std::string &field,
                  const char *unit, const xmlNode *uom_node = nullptr)
    {
      const std::string text = text_of(node);
      char *end = nullptr;
      const double value = std::strtod(text.c_str(), &end);
      if (text.empty() || end == text.c_str() || *end != '\0' || !std::isfinite(value))
        throw ProfileError(doc.file() + ": " + where + ": " + field + " `" + text + "` is not a finite number");
      const std::string uom = attribute(uom_node ? uom_node : node, "uom");
      if (uom != unit)
        throw ProfileError(doc.file() + ": " + where + ": " + field + " is given in `" + uom + "`; CAAML v6 gives it in `" +
                           unit + "` (a file of another schema, or mixed units)");
      return value;
    }

    std::string layer_name(std::size_t k, double depth_top_cm)
    {
      return "layer " + std::to_string(k + 1) + " (top at " + format_number(depth_top_cm, 4) + " cm)";
    }
  } // namespace

  SnowProfile read_caaml_profile(const std::string &file)
  {
    const CaamlDocument doc(file);
    SnowProfile p;
    p.id = attribute(doc.root(), "id"); // gml:id, "SnowPilot-12345"
    const std::string measurements = "c:snowProfileResultsOf/c:SnowProfileMeasurements";
    xmlNode *results = doc.node(measurements, nullptr);
    if (!results)
      throw ProfileError(file + ": no " + measurements + " (a CAAML snow profile without its measurements)");
    const std::string direction = attribute(results, "dir");
    if (!direction.empty() && direction != "top down")
      throw ProfileError(file + ": SnowProfileMeasurements dir=\"" + direction +
                         "\": only depths measured from the surface (\"top down\") are read");

    if (xmlNode *slope = doc.node("c:locRef/c:validSlopeAngle/c:SlopeAnglePosition", nullptr))
      p.slope_angle_deg = number(doc, doc.node("c:position", slope), "slope", "validSlopeAngle", "deg", slope);

    const std::vector<xmlNode *> layers = doc.nodes("c:stratProfile/c:Layer", results);
    for (std::size_t k = 0; k < layers.size(); ++k)
    {
      xmlNode *layer = layers[k];
      ProfileLayer l;
      const double top_cm = number(doc, doc.node("c:depthTop", layer), "layer " + std::to_string(k + 1), "depthTop", "cm");
      const std::string where = layer_name(k, top_cm);
      l.depth_top_m = top_cm * centimetre;
      xmlNode *thickness = doc.node("c:thickness", layer);
      if (!thickness)
        throw ProfileError(file + ": " + where + ": no thickness");
      l.thickness_m = number(doc, thickness, where, "thickness", "cm") * centimetre;
      l.grain_form = text_of(doc.node("c:grainFormPrimary", layer));
      if (xmlNode *size = doc.node("c:grainSize", layer))
        if (xmlNode *average = doc.node("c:Components/c:avg", size))
          l.grain_size_mm = number(doc, average, where, "grainSize/avg", "mm", size);
      const auto hardness = [&](const char *element) -> std::optional<HandHardness> {
        xmlNode *node = doc.node(element, layer);
        if (!node)
          return std::nullopt;
        const auto h = parse_hand_hardness(text_of(node));
        if (!h)
          throw ProfileError(file + ": " + where + ": " + std::string(element).substr(2) + " `" + text_of(node) +
                             "` is not a hand hardness (" + hand_hardness_values + ")");
        return h;
      };
      l.hardness = hardness("c:hardness");
      if (!l.hardness)
      {
        l.hardness = hardness("c:hardnessTop");
        l.hardness_bottom = hardness("c:hardnessBottom");
      }
      p.layers.push_back(l);
    }

    const std::vector<xmlNode *> samples = doc.nodes("c:densityProfile/c:Layer", results);
    for (std::size_t k = 0; k < samples.size(); ++k)
    {
      const std::string where = "density sample " + std::to_string(k + 1);
      DensitySample s;
      s.depth_top_m = number(doc, doc.node("c:depthTop", samples[k]), where, "depthTop", "cm") * centimetre;
      xmlNode *thickness = doc.node("c:thickness", samples[k]);
      if (!thickness)
        throw ProfileError(file + ": " + where + ": no thickness");
      s.thickness_m = number(doc, thickness, where, "thickness", "cm") * centimetre;
      s.density_kg_m3 = number(doc, doc.node("c:density", samples[k]), where, "density", "kgm-3");
      p.density_samples.push_back(s);
    }

    const std::vector<xmlNode *> tests = doc.nodes("c:stbTests/c:PropSawTest", results);
    for (std::size_t k = 0; k < tests.size(); ++k)
    {
      const std::string where = "propagation saw test " + std::to_string(k + 1);
      xmlNode *failed = doc.node("c:failedOn", tests[k]);
      if (!failed)
        throw ProfileError(file + ": " + where + ": no failedOn (a test without a failure gives no cut length)");
      SawTestObservation t;
      t.failed_depth_m = number(doc, doc.node("c:Layer/c:depthTop", failed), where, "failedOn/Layer/depthTop", "cm") * centimetre;
      t.propagation = text_of(doc.node("c:Results/c:fracturePropagation", failed));
      t.cut_length_m = number(doc, doc.node("c:Results/c:cutLength", failed), where, "cutLength", "cm") * centimetre;
      t.column_length_m = number(doc, doc.node("c:Results/c:columnLength", failed), where, "columnLength", "cm") * centimetre;
      t.comment = text_of(doc.node("c:Layer/c:metaData/c:comment", failed));
      p.saw_tests.push_back(t);
    }
    return p;
  }
} // namespace anticrack::profile
